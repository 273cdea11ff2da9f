"""Layer 9, train: training the paper's baselines.

Parameter-shared PPO (``ppo.py``, with ``curiosity.py``, ``networks.py``, ``devices.py``), its
hyperparameters as data (``config.py``, ``hyperparams/``), checkpoints and run directories
(``checkpoint.py``, ``rundir.py``, ``logs.py``), test-seed evaluation (``evaluate.py``), sweeps on Ray
(``grid.py``), learning curves and the committed baselines (``baselines.py``, ``plots.py``). Needs the
``train`` extra (torch). The `hivex train` and `hivex evaluate` commands are the CLI's
(cli/train_commands.py). Imports: base, lang, compiler, adapters, evaluation; never the CLI.
"""

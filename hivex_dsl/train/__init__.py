"""Training the paper's baselines: parameter-shared PPO (``ppo.py``), its hyperparameters as data
(``config.py``, ``hyperparams/``), test-seed evaluation (``evaluate.py``), sweeps on Ray (``grid.py``),
learning curves and the committed baselines (``baselines.py``). Needs the ``train`` extra (torch)."""

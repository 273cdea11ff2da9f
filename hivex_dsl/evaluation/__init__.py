"""Layer 8, evaluation: tools built on the environments, to play, measure and check them.

rollout.py and policies.py (episodes played by random, all-zeros or scripted policies), report.py (what
`hivex run` and `hivex compile` print), audit.py (property checks of a scenario's reward terms),
published.py and fidelity.py (the paper's published results and this toolkit beside them), original/ (the
original release's own curves and average sheets read back from its plot PDFs, and what they show: decision
periods, budgets, learning), bench.py and
bench_expressions.py (steps per second), progress.py (progress bars) and testing.py (hypothesis strategies
for a researcher's own reward-term tests; public as ``hivex_dsl.testing``). Imports: base, lang, sim,
compiler, runtime, envs, adapters (and zoo).
"""

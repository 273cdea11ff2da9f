"""Layer 3, sim: the simulation building blocks every environment shares.

spaces.py and action_arrays.py (observation and action spaces; actions checked and stacked per agent),
batching.py (per-world state in batch arrays), stacking.py (stacked observations shifted once a decision),
statistics.py (the per-episode statistics the original logged), reward/ (reward terms, their contracts and the
composer; expression terms and their vocabulary), fire/ (the wildfire engine of AWS and WRM), procgen/ (terrain,
forest, weather, wind, pollution and layout generators) and render/ (canvas, GIF and PNG). Imports: base, lang. An
environment's expression vocabulary is found by module name (``hivex_dsl.envs.<id>.vocabulary``), never imported
from here.
"""

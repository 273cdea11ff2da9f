"""Aerial Wildfire Suppression's plane rules before issue 52's session 43, for the tests of their mechanics.

Until then planes flew 3 m a step (fitted to Pick Up Water's untrained pages read as one plane's flight), turned
in proportion to the steer, respawned alone over the island when they finished and drew a fresh world every
episode. The release's rules (5 m, a full turn, waiting planes, its spawn and continued worlds) are the defaults
since; these remain params, and the tests that work a mechanism by hand under them say so by using this.
"""

LONE_PLANES = {"plane_speed_m": 3.0, "turn_rule": "proportional", "finished_planes": "respawn", "spawn_rule": "ours",
               "episodes_continue": 0}

# The village's zone and distance and the water before issue 52's session 85, when the release's were made the
# defaults (the reward table's note 'The village's zone, its distance and the water that does not stop the fire')
VILLAGE_AND_WATER_BEFORE = {"village_zone": "circle", "village_distance": "horizontal", "extinguished_spread": False}

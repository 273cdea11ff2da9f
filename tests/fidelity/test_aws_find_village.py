"""benchmarks/aws_find_village.py: trivial planes in Find Village under any params (the AWS reward table's notes)."""

from __future__ import annotations

from ..benchmark_scripts import benchmark_script

script = benchmark_script("aws_find_village")

# a village no plane can come near (the release's 3-D distance from a plane flying 100 m up) and a fire that
# never steps, so it never goes out and ends no world early
NEVER = {"village_radius_m": 0.001, "fire_step_interval": 1000}


def test_planes_that_never_find_the_village_fly_straight_to_the_border():
    """Find Village pays +100 a find and -100 a crossed border, nothing else: straight flights that find nothing
    all cross the border, each paid -100, and their world ends with its last plane, at most the square's diagonal
    (2,121 m) at 5 m a step after the start."""
    ret, share, length = script.first_episodes(NEVER, worlds=3, level=1, policy="zeros")
    assert ret == -100.0 and share == 0.0
    assert 0 < length <= 2121 / 5 + 1


def test_the_same_policy_replays_the_same_worlds_to_the_digit():
    """The worlds depend on the test seed alone: the same policy twice gives the same flights, to the digit."""
    first = script.first_episodes({}, worlds=2, level=1, policy="random")
    assert script.first_episodes({}, worlds=2, level=1, policy="random") == first


def test_the_command_line_prints_both_policies_and_refuses_a_bad_param(capsys):
    assert script.main(["--worlds", "1", "--set", "village_radius_m=0.001", "--set", "fire_step_interval=1000"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == 2 and "zeros: return -100.0 a plane-episode, village found by 0.0% of planes" in lines[0]
    assert "random:" in lines[1]
    assert script.main(["--worlds", "1", "--set", "village_radius_m=-1"]) == 2
    assert "village_radius_m" in capsys.readouterr().err

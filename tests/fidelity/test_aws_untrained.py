"""benchmarks/aws_untrained.py: random planes in each task beside the original's first training point."""

from __future__ import annotations

import pytest

from ..aws_rules import LONE_PLANES
from ..benchmark_scripts import benchmark_script

script = benchmark_script("aws_untrained")


def test_random_planes_pay_pick_up_water_its_time_alone_or_waiting():
    """Pick Up Water pays 100 less a thirtieth a step before the pick-up (tests/fidelity/test_aws_pick_up_water.py):
    a lone plane's return is 100 - (L - 1) / 30, linear in L, so the means obey it too; a waiting plane pays every
    step of its world's L, the pick-up step's thirtieth at most aside."""
    length, ret, original_length, _ = script.untrained("pick_up_water", 3, LONE_PLANES, 4)
    assert ret == pytest.approx(100 - (length - 1) / 30)
    assert 150 < original_length < 250  # the original's untrained planes (194.7 at level 3)
    length, ret, _, _ = script.untrained("pick_up_water", 3, {}, 4)  # the defaults: planes wait for their world
    assert 100 - length / 30 - 1e-9 <= ret <= 100 - (length - 1) / 30 + 1e-9


def test_the_report_names_each_cell_beside_the_original(capsys):
    assert script.main(["--tasks", "drop_water", "--levels", "2", "--episodes", "2"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith("random play, 2 test episodes a cell, params the defaults")
    assert out[1].startswith("  drop_water: L2 ") and out[1].endswith(")")


def test_a_param_out_of_bounds_is_a_clear_error(capsys):
    assert script.main(["--tasks", "drop_water", "--levels", "2", "--set", "plane_speed_m=500"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("aws_untrained: ") and "plane_speed_m" in err and "Traceback" not in err

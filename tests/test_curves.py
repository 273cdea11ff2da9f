"""Learning curves beside the original's: window means, verdicts, and the original's WFC curves as shipped."""

from __future__ import annotations

import pytest

from hivex_dsl.evaluation.curves import compare_curves, comparison_table, original_wfc_main, window_mean


def test_window_mean_takes_the_points_in_the_half_open_window_before_the_step():
    curve = [(100, 1.0), (200, 2.0), (300, 6.0), (400, 10.0)]
    assert window_mean(curve, 300, 200) == pytest.approx(4.0)  # 200 and 300; 100 is on the open end
    assert window_mean(curve, 450, 100) == pytest.approx(10.0)
    assert window_mean(curve, 50, 40) is None


def test_compare_curves_places_our_mean_against_the_band_of_their_runs():
    theirs = [[(s, base + s / 100) for s in range(10, 1001, 10)] for base in (100.0, 110.0, 120.0)]
    # at 100% (window 900-1000, mean step 955): their runs are 109.55, 119.55, 129.55
    inside = compare_curves([[(1000, 115.0)]], theirs, 1000, fractions=(1.0,), window=0.1)[0]
    assert inside.theirs == pytest.approx((109.55, 119.55, 129.55))
    assert inside.band == pytest.approx((109.55, 129.55))
    assert inside.verdict == "inside"
    assert compare_curves([[(1000, 140.0)], [(1000, 130.0)]], theirs, 1000, (1.0,), 0.1)[0].verdict == "above"
    below = compare_curves([[(1000, 100.0)]], theirs, 1000, (1.0,), 0.1)[0]
    assert below.verdict == "below" and below.step == 1000
    # our run has no point between 0 and 100: no verdict at 10%
    early = compare_curves([[(1000, 115.0)]], theirs, 1000, (0.1,), 0.1)[0]
    assert early.ours == (None,) and early.verdict == "no data"


def test_compare_curves_refuses_a_fraction_outside_the_budget():
    with pytest.raises(ValueError):
        compare_curves([], [], 1000, fractions=(1.5,))


def test_the_table_shows_every_run_and_the_verdict():
    point = compare_curves([[(80, 5.0)], [(90, 7.0)]], [[(100, 4.0)], [(100, 8.0)]], 100, (1.0,), 0.5)[0]
    table = comparison_table([point])
    assert "| 100% | 100 | 5, 7 | 6 | 4, 8 | inside |" in table


def test_the_original_wfc_curves_are_the_event_files_points():
    runs = original_wfc_main()
    assert len(runs) == 3 and all(len(run) == 200 for run in runs)
    assert [run[0] for run in runs] == [(40000, 838.1), (40000, 839.8), (40000, 846.9)]
    at_2_44m = [dict(run)[2_440_000] for run in runs]
    assert at_2_44m == pytest.approx([4160.8, 4286.6, 4351.9])  # "about 4,160-4,350 at 2.44M"
    assert runs[0][-1][0] == 8_000_000
    entropy = original_wfc_main("Policy/Entropy")
    assert [run[0][1] for run in entropy] == pytest.approx([1.0961, 1.0961, 1.0961], abs=1e-4)
    with pytest.raises(KeyError):
        original_wfc_main("Losses/Nothing")

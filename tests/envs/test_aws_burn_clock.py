"""When the release's fire steps (params.fire_cadence 'frames', burn_clock.py): the BurnNext coroutine of
ForestDataGenerator, started by Update once a rendered frame while the fire burns and its flag is clear, the flag
cleared by the coroutine's end at the next frame and by ResetForest at a world's redraw (its IL: the reward
table's notes). Worked by hand frame by frame, then played in the simulator."""

from __future__ import annotations

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.envs.aerial_wildfire_suppression.burn_clock import burn_frame, stepping_worlds
from hivex_dsl.runtime import BatchedEnv
from hivex_dsl.sim.procgen.wind import frame_ends

NO = np.array([False])


def frames(events: str) -> str:
    """One world's frames: each character of ``events`` is what happens before that frame's Update: '.' nothing,
    'r' a redraw of the world (ResetForest clears the flag), 'o' its fire is out (the `burning` flag cleared, no
    redraw). Returns a character a frame: 'F' the fire stepped at it, '-' not."""
    running, waiting, out, steps = NO, NO, NO, ""
    for event in events:
        if event == "r":
            running, out = NO, NO  # TriggerDone: ResetForest, then InitiateFire sets `burning`
        elif event == "o":
            out = np.array([True])
        starts, running, waiting = burn_frame(out, running, waiting)
        steps += "F" if starts[0] else "-"
    return steps


def test_one_coroutine_steps_the_fire_every_other_frame():
    assert frames("........") == "F-F-F-F-"


def test_a_redraw_while_a_burnnext_waits_starts_a_second_chain_for_good():
    # the redraw lands after the frame that started a coroutine, before the frame that ends it
    assert frames(".r......") == "FFFFFFFF"
    assert frames("...r....") == "F-FFFFFF"
    assert frames("...r.r..r.") == "F-FFFFFFFF"  # later redraws change nothing


def test_a_redraw_between_chains_keeps_one():
    assert frames("..r.....") == "F-F-F-F-"  # the ended coroutine had cleared the flag: one chain still


def test_a_fire_that_goes_out_stops_both_chains_until_its_redraw():
    assert frames(".r..o...") == "FFFF----"
    assert frames(".r..o..r...") == "FFFF---F-F-"  # a redraw after both ended: one chain again


def compiled(**params):
    return hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression", "task": "main", "agents": 3,
                              "episode_length": 3000, "seeds": {"train": 5000, "test": 6000}, "params": params})


def test_interval_cadence_steps_every_world_together():
    params = compiled(fire_cadence="interval", fire_step_interval=17).params
    running = np.array([False, True])
    assert stepping_worlds(params, 16, NO, running, running)[0] is None  # the 17th step
    worlds, after, _ = stepping_worlds(params, 17, NO, running, running)
    assert not worlds.any() and after is running


def test_the_simulator_steps_the_fire_at_every_other_frame_then_every_frame_after_a_waiting_redraw(aws_fire_ticks):
    env = BatchedEnv(compiled(fire_cadence="frames", episodes_continue=0), batch=2)
    env.reset(seed=0)
    calm = {"continuous": np.zeros((2, 3, 1), np.float32), "discrete": np.zeros((2, 3, 1), np.int64)}
    stepped_at = []
    frame = 50.0 / 3.0
    for _ in range(120):
        tick, before = env.state.tick, len(aws_fire_ticks)
        env.step(calm)
        if len(aws_fire_ticks) > before:
            stepped_at.append((tick, aws_fire_ticks[-1]))
        if tick == 20:  # after the first frame's Update (tick 16) started a BurnNext, before the next frame's end
            assert env.state.burn_waiting.all() and env.state.burn_running.all()
            env.reset_worlds(np.array([True, False]))  # world 0 redrawn while its BurnNext waits
    frame_ticks = [t for t in range(120) if frame_ends(t, frame)]
    assert frame_ticks[:4] == [16, 33, 49, 66]
    # both worlds at the first frame; then world 0 alone at every frame end, both at every other one
    expected = [(16, 2)] + [(t, 1 if i % 2 else 2) for i, t in enumerate(frame_ticks[1:], 1)]
    assert stepped_at == expected


def test_worlds_stepping_apart_stay_deterministic():
    def played(seed: int) -> np.ndarray:
        env = BatchedEnv(compiled(fire_cadence="frames", episodes_continue=0), batch=3)
        env.reset(seed=seed)
        calm = {"continuous": np.zeros((3, 3, 1), np.float32), "discrete": np.zeros((3, 3, 1), np.int64)}
        for tick in range(134):
            env.step(calm)
            if tick == 20:
                env.reset_worlds(np.array([False, True, False]))  # world 1 alone steps at every frame from here
        assert env.state.burn_waiting.tolist() == [False, True, False]  # the frame ended at tick 133 stepped world 1 alone
        return env.state.fire.trees.copy()

    first = played(3)
    assert np.array_equal(first, played(3))
    assert not np.array_equal(first, played(4))

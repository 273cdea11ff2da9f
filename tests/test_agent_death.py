"""Agent death as stock consumers see it: per-slot episodes with a flag on the death step and a respawn.

Deaths are forced deterministically: vessels at full throttle and planes flying straight ahead
cross the border (OPC's crash ends a vessel's episode; AWS's border ends a plane's).
RecordEpisodeStatistics, SuperSuit's vector conversion and the flat wrappers must all count the
same per-agent returns and lengths as the toolkit's own ``hivex_episode`` sums, and those must
equal the rewards summed by hand under Gymnasium's autoreset rules.

Endings have a scope: agents whose own endings coincide (DBR drones draining alike, a one-agent
world's only agent) respawn in their running world; only the clock or a declared world-level ending
(AWS/WRM fire out, a per-world ending expression) restarts a world.
"""

from __future__ import annotations

import numpy as np
import pytest
from gymnasium import spaces
from gymnasium.vector import AutoresetMode
from gymnasium.wrappers.vector import RecordEpisodeStatistics

import hivex_dsl
from hivex_dsl.adapters.flat import FlatParallelEnv, flat_vector_env

from .aws_rules import LONE_PLANES

# Long enough for an agent flying straight to reach the border from any spawn, so every one dies at least once
# whatever the seed: an AWS plane (5 m a step) crosses the +/-750 m square's diagonal (2,121 m) in 425 steps.
LENGTH = {"ocean_plastic_collection": 400, "aerial_wildfire_suppression": 430}


def scenario(environment: str) -> dict:
    # period 1 (OPC defaults to 5): the deaths below are counted in physics steps, one a step() call. OPC's crash
    # ends the crashed vessel alone here (crash_outcome: end): its default, end_world, ends the whole world's episode
    extra = {"params": {"crash_outcome": "end"}} if environment == "ocean_plastic_collection" else {}
    if environment == "aerial_wildfire_suppression":  # a plane's own ending: the lone planes (the release's wait)
        extra = {"params": LONE_PLANES}
    return {"hivex": 1, "environment": environment, "episode_length": LENGTH[environment], "decision_period": 1,
            "seeds": {"train": 1, "test": 2}, **extra}


def straight_ahead(environment: str, slots: int, flat: bool = False):
    """Full throttle, no steering (OPC); no steering, no drop (AWS): every agent ends at the border."""
    if environment == "ocean_plastic_collection":
        return np.tile([1, 0], (slots, 1))
    if flat:  # continuous 0 (straight), discrete bin 0 (no drop)
        return np.tile(np.array([0.0, -1.0], np.float32), (slots, 1))
    return {"continuous": np.zeros((slots, 1), np.float32), "discrete": np.zeros((slots, 1), np.int64)}


def hand_counted(rewards, dones, mode):
    """Per-slot (return, length) of finished episodes, from the raw step results by Gymnasium's rules."""
    slots = rewards[0].shape[0]
    ret, length, prev, out = np.zeros(slots), np.zeros(slots, int), np.zeros(slots, bool), []
    for r, d in zip(rewards, dones):
        counted = np.ones(slots, bool) if mode is AutoresetMode.SAME_STEP else ~prev
        if mode is AutoresetMode.NEXT_STEP:
            assert np.all(r[prev] == 0.0)  # the restart step of a slot gives reward 0
            ret[prev], length[prev] = 0.0, 0
        ret[counted] += r[counted]
        length[counted] += 1
        out.append([(s, ret[s], length[s]) for s in np.flatnonzero(d)])
        if mode is AutoresetMode.SAME_STEP:
            ret[d], length[d] = 0.0, 0
        prev = d
    return out


def record_step(infos, reward, done, record) -> None:
    """Keep one step's rewards, endings and our episode summaries in ``record`` (rewards, dones, ours);
    the wrapper's episode statistics and ours must agree slot by slot, and so must the flags."""
    rewards, dones, ours = record
    rewards.append(reward)
    dones.append(done)
    ours.append([(s, infos["hivex_episode"]["return"][s], infos["hivex_episode"]["length"][s])
                 for s in np.flatnonzero(done)])
    if not done.any():
        assert "hivex_episode" not in infos and "episode" not in infos
        return
    np.testing.assert_array_equal(infos["_episode"], done)
    np.testing.assert_array_equal(infos["_hivex_episode"], done)
    np.testing.assert_allclose(infos["episode"]["r"], infos["hivex_episode"]["return"], rtol=1e-9, atol=1e-9)
    np.testing.assert_array_equal(infos["episode"]["l"], infos["hivex_episode"]["length"])


def assert_summed_as_by_hand(record, mode) -> int:
    """Our episode summaries equal the rewards summed by hand; returns the number of finished episodes."""
    rewards, dones, ours = record
    by_hand = hand_counted(rewards, dones, mode)
    for mine, theirs in zip(ours, by_hand):
        assert [(s, length) for s, _, length in mine] == [(s, length) for s, _, length in theirs]
        np.testing.assert_allclose([r for _, r, _ in mine], [r for _, r, _ in theirs], rtol=1e-9, atol=1e-9)
    return sum(len(step) for step in by_hand)


@pytest.mark.ecosystem("gymnasium")
@pytest.mark.parametrize("environment", list(LENGTH))
@pytest.mark.parametrize("mode", ["next_step", "same_step"])
@pytest.mark.parametrize("flat", [False, True])
def test_record_episode_statistics_counts_what_the_toolkit_sums_including_deaths(environment, mode, flat):
    venv = hivex_dsl.vector_env(scenario(environment), num_worlds=2, autoreset_mode=mode)
    if flat:
        venv = flat_vector_env(venv)
    stats = RecordEpisodeStatistics(venv)
    stats.reset(seed=3)
    actions = straight_ahead(environment, stats.num_envs, flat)
    record, deaths, finished = ([], [], []), 0, 0
    for _ in range(LENGTH[environment] + 3):
        obs, reward, terminated, truncated, infos = stats.step(actions)
        assert stats.observation_space.contains(obs)
        record_step(infos, reward, terminated | truncated, record)
        deaths += int(np.count_nonzero(terminated & ~truncated))
        finished += int(np.count_nonzero(terminated | truncated))
    assert deaths >= 2 and finished > deaths  # agents died alone, and worlds ran out of time later
    assert assert_summed_as_by_hand(record, stats.metadata["autoreset_mode"]) == finished


@pytest.mark.parametrize("environment", list(LENGTH))
def test_a_dead_slot_comes_back_with_a_first_observation_and_plays_on(environment):
    venv = hivex_dsl.vector_env(scenario(environment), num_worlds=1)
    venv.reset(seed=3)
    actions = straight_ahead(environment, venv.num_envs)
    for _ in range(LENGTH[environment]):
        obs, reward, terminated, truncated, infos = venv.step(actions)
        if terminated.any() and not truncated.any():
            break
    slot = int(np.flatnonzero(terminated)[0])
    assert infos["hivex_episode"]["length"][slot] > 0
    obs, reward, terminated, truncated, infos = venv.step(actions)  # NEXT_STEP: the slot restarts
    assert reward[slot] == 0.0 and not terminated[slot] and not truncated[slot]
    assert abs(obs["vector"][slot, 0]) < 1.0 and abs(obs["vector"][slot, 1]) < 1.0  # back inside the border
    for _ in range(3):
        obs, reward, terminated, truncated, infos = venv.step(actions)
    assert not terminated[slot]  # it plays on: its steps count in its new episode


@pytest.mark.ecosystem("supersuit")
@pytest.mark.parametrize("environment", list(LENGTH))
def test_supersuit_vector_conversion_counts_per_agent_returns_including_deaths(environment):
    supersuit = pytest.importorskip("supersuit")
    env = FlatParallelEnv(hivex_dsl.parallel_env(scenario(environment), respawn=True))
    venv = supersuit.pettingzoo_env_to_vec_env_v1(env)
    venv.reset(seed=3)
    actions = straight_ahead(environment, venv.num_envs, flat=True)
    ret, length = np.zeros(venv.num_envs), np.zeros(venv.num_envs, int)
    deaths = episodes = 0
    for _ in range(LENGTH[environment] + 3):
        obs, reward, terminated, truncated, infos = venv.step(actions)
        ret += reward
        length += 1
        for slot in np.flatnonzero(terminated | truncated):  # SuperSuit restarts a slot within the step
            summary = infos[slot]["hivex_episode"]
            assert summary["length"] == length[slot]
            assert summary["return"] == pytest.approx(ret[slot], rel=1e-5, abs=1e-4)  # SuperSuit sums float32
            assert "terminal_observation" in infos[slot]
            ret[slot], length[slot] = 0.0, 0
            deaths += bool(terminated[slot]) and not truncated.any()
            episodes += 1
    assert deaths >= 2 and episodes > deaths


@pytest.mark.parametrize("environment", list(LENGTH))
def test_the_parallel_env_keeps_pettingzoo_semantics_by_default(environment):
    env = hivex_dsl.parallel_env(scenario(environment))
    env.reset(seed=3)
    left = None
    for _ in range(LENGTH[environment]):
        actions = {a: (np.array([1, 0]) if environment == "ocean_plastic_collection" else
                       {"continuous": np.zeros(1, np.float32), "discrete": np.zeros(1, np.int64)}) for a in env.agents}
        _, _, terminated, truncated, infos = env.step(actions)
        gone = [a for a in terminated if terminated[a] and not truncated[a]]
        if gone and env.agents:
            left = gone[0]
            break
    assert left is not None and left not in env.agents and "hivex_episode" in infos[left]


@pytest.mark.ecosystem("sb3")
@pytest.mark.parametrize("environment", list(LENGTH))
def test_sb3_vec_monitor_counts_per_agent_returns_including_deaths(environment):
    pytest.importorskip("stable_baselines3")
    from stable_baselines3.common.vec_env import VecMonitor

    from hivex_dsl.adapters.sb3 import SB3VecEnv

    venv = VecMonitor(SB3VecEnv(scenario(environment), num_worlds=2))
    venv.seed(3)
    venv.reset()
    actions = straight_ahead(environment, venv.num_envs, flat=True)
    deaths = episodes = 0
    for _ in range(LENGTH[environment] + 3):
        obs, reward, dones, infos = venv.step(actions)
        assert all(venv.observation_space.contains(o) for o in obs)  # SB3 spaces are one slot's
        for slot in np.flatnonzero(dones):
            mine, monitor = infos[slot]["hivex_episode"], infos[slot]["episode"]
            assert monitor["l"] == mine["length"]
            assert monitor["r"] == pytest.approx(mine["return"], rel=1e-5, abs=1e-4)  # VecMonitor sums float32
            assert venv.observation_space.contains(infos[slot]["terminal_observation"])
            deaths += not infos[slot]["TimeLimit.truncated"]
            episodes += 1
    assert deaths >= 2 and episodes > deaths


@pytest.mark.parametrize("environment", ["ocean_plastic_collection", "aerial_wildfire_suppression",
                                         "drone_based_reforestation"])
def test_respawn_where_restarts_only_the_masked_agents(environment):
    from hivex_dsl.runtime import BatchedEnv

    core = BatchedEnv(hivex_dsl.compile({"hivex": 1, "environment": environment, "episode_length": 50}), batch=2)
    core.reset(seed=0)
    space = core.sim.action_space
    space.seed(0)
    for _ in range(5):
        sample = [space.sample() for _ in range(2 * core.agents)]
        actions = ({k: np.stack([s[k] for s in sample]).reshape((2, core.agents) + space[k].shape) for k in space.spaces}
                   if isinstance(space, spaces.Dict) else np.stack(sample).reshape((2, core.agents) + space.shape))
        core.step(actions)
    before = core.observe()
    mask = np.zeros((2, core.agents), bool)
    mask[1, 0] = True
    state = core.sim.respawn_where(core.state, mask, np.random.default_rng(1))
    after = core.sim.observe(state)
    for key in before:
        np.testing.assert_array_equal(after[key][~mask], before[key][~mask])  # the others are untouched
        assert core.sim.observation_space[key].contains(np.asarray(after[key][1, 0]))
    if environment == "drone_based_reforestation":
        assert state.energy[1, 0] == 1.0 and state.alive[1, 0]
        first = after["vector"][1, 0]  # a first observation: the older stack zeros, as ML-Agents resets it
        assert first[:10].any() and not first[10:].any()
    if environment == "ocean_plastic_collection":
        assert state.active[1, 0] and state.speed[1, 0] == 0.0 and state.collected_total[1, 0] == 0
        assert core.state.nearby_best[1, 0] > 0 and state.nearby_best[1, 0] == 0  # a new ML-Agents episode: the running maximum starts from 0 again
        np.testing.assert_array_equal(state.nearby_best[~mask], core.state.nearby_best[~mask])
    if environment == "aerial_wildfire_suppression":
        assert state.flying[1, 0] and not state.seen_fire[1, 0]


# --- The scope of an ending: an agent's own (it respawns) or its world's (the world restarts) ---------------

ONE_EPISODE = 60
LAYOUT = {  # per-world arrays a world restart draws anew and no step changes
    "drone_based_reforestation": lambda s: (s.heights, s.tree_xy, s.station, s.new_trees, s.new_count),
    "ocean_plastic_collection": lambda s: (s.heat,),
    "aerial_wildfire_suppression": lambda s: (s.maps.ground, s.maps.village),
    "wildfire_resource_management": lambda s: (s.fire_factors,),
}


def short_battery(agents: int = 3, **extra) -> dict:
    """DBR whose batteries last 12 steps (the smallest bound is 10; a drone charges at the station only on a
    return, so they drain from the first step); every drone starts above the station itself."""
    return {"hivex": 1, "environment": "drone_based_reforestation", "episode_length": ONE_EPISODE, "agents": agents,
            "decision_period": 1, "seeds": {"train": 1, "test": 2},  # steps counted as physics steps
            "params": {"energy_steps_with_seed": 12, "energy_steps_without_seed": 12,
                       "spawn_radius_m": 0.0, "spawn_gap_m": 0.0}, **extra}


def climbing(slots: int):
    """No throttle, no steering, full climb, no drop: drones spawned at one point above the station leave its
    charge radius on the same step, drain alike, and (never docking again) die on the same step."""
    continuous = np.zeros((slots, 3), np.float32)
    continuous[:, 2] = 1.0
    return {"continuous": continuous, "discrete": np.zeros((slots, 1), np.int64)}


def layout(environment: str, state) -> list[np.ndarray]:
    return [np.array(a, copy=True) for a in LAYOUT[environment](state)]


def assert_same_worlds(environment: str, state, start: list[np.ndarray], worlds) -> None:
    for now, then in zip(layout(environment, state), start):
        np.testing.assert_array_equal(now[worlds], then[worlds])


DEATH_CASES = [("drone_based_reforestation", 3), ("drone_based_reforestation", 1),
               ("ocean_plastic_collection", 1), ("aerial_wildfire_suppression", 1)]


def death_case(environment: str, agents: int):
    """(scenario, actions for n slots, episode length) of a case whose agents all die on one step."""
    if environment == "drone_based_reforestation":
        return short_battery(agents), climbing, ONE_EPISODE
    actions = lambda slots: straight_ahead(environment, slots)  # noqa: E731
    return dict(scenario(environment), agents=agents), actions, LENGTH[environment]


@pytest.mark.parametrize("environment,agents", DEATH_CASES)
@pytest.mark.parametrize("mode", ["next_step", "same_step"])
def test_agents_that_all_die_on_one_step_respawn_in_the_same_world(environment, agents, mode):
    """Individual endings that coincide (every drone's battery, a one-agent world's only agent) end those
    agents' episodes, never their world's: the clock runs on and the world's layout stays until the clock
    runs out; the episode statistics still match the toolkit's sums and the rewards summed by hand."""
    sc, act, length = death_case(environment, agents)
    venv = hivex_dsl.vector_env(sc, num_worlds=2, autoreset_mode=mode)
    stats = RecordEpisodeStatistics(venv)
    stats.reset(seed=3)
    core, actions = venv.core, act(stats.num_envs)
    start = layout(environment, core.state)
    record, together = ([], [], []), 0
    for t in range(length + 3):
        obs, reward, terminated, truncated, infos = stats.step(actions)
        assert stats.observation_space.contains(obs)
        record_step(infos, reward, terminated | truncated, record)
        if t < length - 1:  # inside the first episode: deaths only, and no world restarts
            assert not truncated.any()
            together += int(np.count_nonzero(terminated.reshape(2, agents).all(axis=1)))
            np.testing.assert_array_equal(core.clock, [t + 1, t + 1])
            assert_same_worlds(environment, core.state, start, slice(None))
    assert together >= 1  # every agent of a world died on one step (the old rule restarted the world then)
    assert assert_summed_as_by_hand(record, stats.metadata["autoreset_mode"]) > 0
    with pytest.raises(AssertionError):  # the clock's end does restart the worlds: the layout is a new one
        assert_same_worlds(environment, core.state, start, slice(None))


FIRE_OUT_STEP = 5


def fire_out_in_world_zero(restepped, environment: str):
    """``environment``'s main task (it ends on ``fire_out``) with the fire of world 0 going out on step 5."""
    calls = [0]

    def step(sim, state, actions, rng):
        new, outcome = sim.step(state, actions, rng)
        calls[0] += 1
        events = dict(outcome.events)
        events["fire_out"] = events["fire_out"].copy()
        events["fire_out"][0] |= calls[0] == FIRE_OUT_STEP  # a world event holds for every agent of its world
        return new, outcome._replace(events=events)

    # AWS's lone planes draw a fresh world every episode; under episodes_continue (the release's) a world is drawn
    # afresh when its fire is out, not on this event alone, which the test forces while the fire still burns
    lone = {"params": LONE_PLANES} if environment == "aerial_wildfire_suppression" else {}
    compiled = hivex_dsl.compile({"hivex": 1, "environment": environment, "episode_length": ONE_EPISODE,
                                  "seeds": {"train": 1, "test": 2}, **lone})
    assert "fire_out" in compiled.ends_on and "fire_out" in compiled.entry.world_events
    return restepped(compiled, step)


@pytest.mark.parametrize("environment", ["aerial_wildfire_suppression", "wildfire_resource_management"])
@pytest.mark.parametrize("mode", ["next_step", "same_step"])
def test_fire_out_is_a_world_ending_that_restarts_the_world(restepped, environment, mode):
    venv = hivex_dsl.vector_env(fire_out_in_world_zero(restepped, environment), num_worlds=2, autoreset_mode=mode)
    stats = RecordEpisodeStatistics(venv)
    stats.reset(seed=3)
    core, agents = venv.core, venv.agents_per_world
    actions = np.stack([stats.single_action_space.sample() for _ in range(stats.num_envs)]) \
        if not isinstance(stats.single_action_space, spaces.Dict) else straight_ahead(environment, stats.num_envs)
    start = layout(environment, core.state)
    for _ in range(FIRE_OUT_STEP - 1):
        _, _, terminated, truncated, _ = stats.step(actions)
        assert not (terminated | truncated).any()
    _, _, terminated, truncated, infos = stats.step(actions)
    world0 = np.arange(stats.num_envs) < agents
    np.testing.assert_array_equal(terminated, world0)  # every agent of world 0 ends, nobody of world 1
    assert not truncated.any()
    np.testing.assert_array_equal(infos["episode"]["l"][world0], FIRE_OUT_STEP)
    np.testing.assert_array_equal(infos["hivex_episode"]["length"][world0], FIRE_OUT_STEP)
    if mode == "next_step":  # world 0 restarts on the next step (its rewards 0, no ending)
        _, reward, terminated, truncated, _ = stats.step(actions)
        assert not (terminated | truncated).any() and np.all(reward[world0] == 0.0)
    np.testing.assert_array_equal(core.clock, [0, FIRE_OUT_STEP + (mode == "next_step")])
    assert_same_worlds(environment, core.state, start, [1])
    with pytest.raises(AssertionError):  # world 0 is a new one
        assert_same_worlds(environment, core.state, start, [0])


@pytest.mark.parametrize("scope,world_restarts", [("altitude_m > 15", False), ("team_min(altitude_m) > 15", True)])
def test_a_per_world_ending_expression_ends_the_world_and_a_per_agent_one_its_agents(scope, world_restarts):
    """Climbing drones cross 15 m together: the per-agent expression ends each drone (they respawn, the
    world goes on), the per-world one (a value of the whole world) ends the world."""
    scenario = short_battery(3, ends_on=[scope])
    # batteries that outlast the climb past 15 m: they drain from the first step, on the station's pad too
    scenario["params"] |= {"energy_steps_with_seed": 40, "energy_steps_without_seed": 40}
    venv = hivex_dsl.vector_env(scenario, num_worlds=1, autoreset_mode="same_step")
    venv.reset(seed=3)
    actions = climbing(venv.num_envs)
    for t in range(ONE_EPISODE - 1):
        _, _, terminated, truncated, _ = venv.step(actions)
        if terminated.any():
            break
    assert terminated.all() and not truncated.any()
    assert venv.core.clock[0] == (0 if world_restarts else t + 1)


@pytest.mark.parametrize("respawn", [False, True])
def test_the_parallel_env_ends_a_one_drone_world_only_with_respawn_off(respawn):
    env = hivex_dsl.parallel_env(short_battery(1), respawn=respawn)
    env.reset(seed=3)
    action = {"continuous": np.array([0.0, 0.0, 1.0], np.float32), "discrete": np.zeros(1, np.int64)}
    for t in range(ONE_EPISODE - 1):
        obs, _, terminated, truncated, infos = env.step({a: action for a in env.agents})
        if terminated["drone_0"]:
            break
    assert terminated["drone_0"] and not truncated["drone_0"] and infos["drone_0"]["hivex_episode"]["length"] == t + 1
    if respawn:  # respawned in its world: a full battery, the clock runs on
        assert env.agents == ["drone_0"] and "terminal_observation" in infos["drone_0"]
        assert env.core.state.energy[0, 0] == 1.0 and env.core.clock[0] == t + 1
    else:  # PettingZoo's rule: the ended agent leaves, and with nobody left the episode is over
        assert env.agents == []


def test_the_fire_going_out_and_an_ocean_crash_are_the_declared_endings_of_a_whole_world():
    import dataclasses

    from hivex_dsl.compiler import registry

    declared = {env: registry.get(env).world_events for env in LAYOUT | {"wind_farm_control": None}}
    assert declared == {"aerial_wildfire_suppression": {"fire_out"}, "wildfire_resource_management": {"fire_out"},
                        "drone_based_reforestation": set(), "ocean_plastic_collection": {"crash_ended_world"},
                        "wind_farm_control": set()}
    entry = registry.get("drone_based_reforestation")
    with pytest.raises(ValueError, match="world events \\['fire_out'\\] are not among its events"):
        registry.register(dataclasses.replace(entry, world_events=frozenset({"fire_out"})))


def uneven_batteries(agents: int = 2) -> dict:
    """DBR whose batteries last 12 steps holding a seed and 48 without, so a drone that drops its seed outlives one
    that keeps it: within a world, one drone ends while another plays on."""
    sc = short_battery(agents)
    return dict(sc, params=dict(sc["params"], energy_steps_without_seed=48,
                                drop_min_distance_m=7.5))  # drop as soon as the climb leaves the charge radius


def climb_and_drop(slots: int):
    """Climb straight up; the even slots try to drop their seed at every step, the odd ones keep theirs."""
    actions = climbing(slots)
    actions["discrete"][0::2, 0] = 1
    return actions


@pytest.mark.parametrize("mode", ["next_step", "same_step"])
def test_with_ended_agents_wait_a_drone_out_of_energy_sits_out_until_its_world_restarts(mode):
    """ended_agents="wait": a drone whose battery ran out is not respawned; until its world restarts its slot is
    inactive (infos["active"] False), earns 0, ends nothing and logs no episode, its battery stays empty; a world
    restarts at its clock's end or once all its drones have ended; and so every logged episode began at its
    world's start, its length the world's clock (with "respawn" a respawned drone's episode is cut short)."""
    venv = hivex_dsl.vector_env(uneven_batteries(), num_worlds=2, autoreset_mode=mode, ended_agents="wait")
    _, infos = venv.reset(seed=3)
    assert infos["active"].all()
    core, actions = venv.core, climb_and_drop(venv.num_envs)
    waiting = np.zeros(venv.num_envs, bool)  # slots out of play, by this test's own count
    waited_beside_a_player, episodes = 0, 0
    for _ in range(3 * ONE_EPISODE):
        clock_before = core.clock.copy()
        _, reward, terminated, truncated, infos = venv.step(actions)
        ended = terminated | truncated
        assert not ended[waiting].any() and (reward[waiting] == 0.0).all()
        if "_hivex_episode" in infos:
            slots = np.flatnonzero(infos["_hivex_episode"])
            # the world's clock at this ending (SAME_STEP has restarted an ended world already)
            world_clock = np.where(core.clock == 0, clock_before + 1, core.clock)
            np.testing.assert_array_equal(infos["hivex_episode"]["length"][slots],
                                          world_clock[slots // 2])
            episodes += slots.size
        restarted = (core.clock == 0) if mode == "same_step" else (core.clock < clock_before)
        waiting = (waiting | ended) & ~np.repeat(restarted, 2)
        energy = core.state.energy.reshape(-1)
        if mode == "next_step":  # a slot that ended this step still shows its last observation
            waiting_now = waiting & ~ended
            assert (energy[waiting_now] <= 0.0).all()
            np.testing.assert_array_equal(infos["active"], core.alive.reshape(-1))
        waited_beside_a_player += int(np.count_nonzero((waiting & ~ended).reshape(2, 2).any(axis=1)
                                                       & core.alive.any(axis=1)))
    assert episodes > 4 and waited_beside_a_player > 0  # the case happened: one drone sat out while another flew


def test_with_ended_agents_respawn_a_drone_out_of_energy_flies_again_in_its_running_world():
    """The default: the same drone respawns at once with a full battery and its world's clock runs on, so its next
    episode ends at the world's end, shorter than the world's clock (a tail)."""
    venv = hivex_dsl.vector_env(uneven_batteries(), num_worlds=2)
    _, infos = venv.reset(seed=3)
    assert "active" not in infos
    core, actions = venv.core, climb_and_drop(venv.num_envs)
    tails = 0
    for _ in range(3 * ONE_EPISODE):
        _, _, _, _, infos = venv.step(actions)
        assert "active" not in infos
        if "_hivex_episode" in infos:
            slots = np.flatnonzero(infos["_hivex_episode"])
            tails += int(np.count_nonzero(infos["hivex_episode"]["length"][slots] < core.clock[slots // 2]))
    assert tails > 0


def test_ended_agents_takes_only_its_two_words():
    with pytest.raises(ValueError, match="ended_agents must be one of \\['respawn', 'wait'\\], got 'stay'"):
        hivex_dsl.vector_env(uneven_batteries(), ended_agents="stay")

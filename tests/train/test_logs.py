"""Episode summaries are read under either key name, only for the slots that ended, never empty ones."""

from __future__ import annotations

import numpy as np
import pytest

from hivex_dsl.train.logs import EpisodeLog, episode_summaries


def _infos(key: str):
    return {key: {"return": np.array([5.0, 0.0, 7.0, 0.0]), "length": np.array([10, 0, 12, 0]),
                  "reward_terms": {"a": np.array([5.0, 0.0, 7.0, 0.0])},
                  "statistics": {"Water Pickup": np.array([1.0, 0.0, 3.0, 0.0])}},
            f"_{key}": np.array([True, True, True, False])}


@pytest.mark.parametrize("key", ["hivex_episode", "episode"])
def test_summaries_of_ended_slots_only(key):
    summary = episode_summaries(_infos(key))
    # slot 1 ended with an empty episode (it restarted on the step its world ended): no experience
    assert summary["return"].tolist() == [5.0, 7.0]
    assert summary["statistics"]["Water Pickup"].tolist() == [1.0, 3.0]
    assert episode_summaries({"reward_terms": {}}) is None


def test_the_log_drains_means():
    log = EpisodeLog()
    log.record(_infos("hivex_episode"))
    log.record({"reward_terms": {}})
    drained = log.drain()
    assert drained["return"] == 6.0 and drained["episodes"] == 2 and drained["length"] == 11.0
    assert drained["reward_terms"] == {"a": 6.0} and drained["statistics"] == {"Water Pickup": 2.0}
    assert log.drain() == {}

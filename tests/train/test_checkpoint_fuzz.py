"""A checkpoint file with any field removed, retyped or bit-flipped is refused with one TrainError sentence that
names the file (exit 2 and one line through the CLI), never another exception; its weights and training state
carry SHA-256 checksums, so one flipped bit is refused too. The random mutations run a few cases by default and
many more with HIVEX_FUZZ_LONG=1."""

from __future__ import annotations

import copy
import math
import os
from pathlib import Path
from typing import Any

import pytest
import torch
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from hivex_dsl.cli import main
from hivex_dsl.compiler import compile
from hivex_dsl.train.checkpoint import (FORMAT, OLDER_FORMATS, checksum, load_checkpoint, policy_for, resume_state,
                                        seal, sections)
from hivex_dsl.train.config import TrainError, make_config
from hivex_dsl.train.ppo import train

from .conftest import TINY, short_scenario

# WRM: curiosity ships in its paper hyperparameters, so the training state holds every section
ONE_UPDATE = {"buffer_size": 90, "batch_size": 90, "num_epoch": 1, "max_steps": 90}
# ("format" missing or wrong was refused before checksums, and tests/train/test_train.py checks it)
REQUIRED = ("model", "config", "scenario", "fingerprint", "agent_steps")
RETYPES = (None, "x", [1], 3)
VALID_RETYPES = [("agent_steps", 3), ("wall_s", None), ("wall_s", 3), ("fingerprint", "x"), ("checksums", None)]
FUZZ_CASES = 1000 if os.environ.get("HIVEX_FUZZ_LONG") == "1" else 25
WEIGHT = "actor.mlp.0.weight"


@pytest.fixture(scope="module")
def run(tmp_path_factory) -> dict[str, Any]:
    """A tiny WRM run: its checkpoint's content, scenario and hyperparameters."""
    compiled = compile(short_scenario("wildfire_resource_management", episode_length=8))
    cfg = make_config(compiled.environment, TINY | ONE_UPDATE)
    folder = tmp_path_factory.mktemp("run")
    train(compiled, cfg, folder, progress=False)
    data = torch.load(folder / "checkpoint.pt", weights_only=True)
    return {"data": data, "compiled": compiled, "cfg": cfg, "file": folder / "checkpoint.pt"}


def written(data: dict[str, Any], path: Path) -> Path:
    torch.save(data, path)
    return path


def resealed(data: dict[str, Any]) -> dict[str, Any]:
    """``data`` with the checksums a checkpoint saved with this content would carry."""
    return data | {"checksums": seal(data)}


def refusal(path: Path, run: dict[str, Any]) -> TrainError | None:
    """None where ``path`` loads, plays and resumes as the run's checkpoint; else the TrainError that refuses it
    (any other exception fails the test)."""
    try:
        loaded = load_checkpoint(path)
        policy_for(loaded, loaded["compiled"])
        resume_state(path, run["compiled"], run["cfg"])
    except TrainError as exc:
        assert "\n" not in str(exc) and str(path) in str(exc), str(exc)
        return exc
    return None


def refused(path: Path, run: dict[str, Any]) -> str:
    exc = refusal(path, run)
    assert exc is not None, "accepted"
    return str(exc)


def flip_bit(tensor: torch.Tensor, element: int = 0, bit: int = 0) -> None:
    """Flip one bit of one element of ``tensor``, in place."""
    as_bytes = tensor.view(-1).view(torch.uint8)
    index = element * tensor.element_size() + bit // 8
    as_bytes[index] ^= 1 << (bit % 8)


def test_checkpoints_carry_checksums_of_every_field(run, tmp_path):
    assert run["data"]["format"] == FORMAT
    assert run["data"]["checksums"] == resealed(run["data"])["checksums"]
    assert set(run["data"]["checksums"]) == {"model", "training", "fields"}
    assert refusal(run["file"], run) is None
    no_wall = {k: v for k, v in run["data"].items() if k != "wall_s"}  # wall_s came later: None when absent
    assert load_checkpoint(written(resealed(no_wall), tmp_path / "no_wall_s.pt"))["agent_steps"] == 90
    weights_only = {k: v for k, v in run["data"].items() if k != "training"}  # a numbered checkpoint
    assert load_checkpoint(written(resealed(weights_only), tmp_path / "weights.pt"))["agent_steps"] == 90


@pytest.mark.parametrize("field,value", [("agent_steps", 10**9), ("agent_steps", 0), ("wall_s", 0.5),
                                         ("fingerprint", "sha256:0"), ("format", OLDER_FORMATS[0])])
def test_every_field_is_covered_by_a_checksum(field, value, run, tmp_path):
    """Issue 54, item 5: only the weights and the training state were checksummed, so ``agent_steps`` set to 10**9
    resumed and trained nothing."""
    path = written(run["data"] | {field: value}, tmp_path / "c.pt")
    assert refused(path, run) == (f"{path} is corrupt: its fields (format, config, scenario, fingerprint, "
                                  "agent_steps, wall_s) do not match their checksum")


def test_a_checkpoint_without_checksums_is_refused(run, tmp_path):
    """Issue 54, item 5: one without its ``checksums`` loaded changed weights as an "older" checkpoint."""
    data = {k: v for k, v in copy.deepcopy(run["data"]).items() if k != "checksums"}
    data["model"][WEIGHT][0, 0] += 1.0
    path = written(data, tmp_path / "c.pt")
    assert refused(path, run).startswith(f"{path} carries no checksums, so nothing says its weights, scenario and "
                                         "agent-steps are what training saved")


def test_a_scenario_edited_under_its_fingerprint_is_refused_even_resealed(run, tmp_path):
    """Issue 54, item 5: an edited ``scenario`` with the fingerprint kept made `hivex evaluate` play another scenario
    under the same name; resealing the checksums does not hide it, as the fingerprint is the scenario's content."""
    data = copy.deepcopy(run["data"])
    data["scenario"]["episode_length"] = 9
    path = written(resealed(data), tmp_path / "c.pt")
    assert refused(path, run) == (f"{path} is corrupt: its scenario's fingerprint is "
                                  f"{compile(data['scenario']).fingerprint}, not the {run['compiled'].fingerprint} it "
                                  "trained on (its scenario was edited after training)")


@pytest.mark.parametrize("environment", [["wildfire_resource_management"], {"name": 1}, 7])
def test_a_scenario_whose_environment_is_no_name_is_refused_with_a_train_error(run, tmp_path, environment):
    """Found by the fuzz below: a list there once reached the registry's dict lookup and raised TypeError."""
    data = copy.deepcopy(run["data"])
    data["scenario"]["environment"] = environment
    assert "environment" in refused(written(resealed(data), tmp_path / "c.pt"), run)


def test_a_checkpoint_of_the_older_format_plays_but_does_not_resume(run, tmp_path):
    """Format 1 checksummed the weights and the training state only: it still plays and evaluates, its scenario
    checked against its fingerprint, but its agent-steps and hyperparameters are not covered, so no run goes on."""
    older = {k: v for k, v in run["data"].items() if k != "checksums"} | {"format": OLDER_FORMATS[0]}
    older["checksums"] = {section: value for section, value in seal(older).items() if section != "fields"}
    path = written(older, tmp_path / "older.pt")
    loaded = load_checkpoint(path)
    policy_for(loaded, loaded["compiled"])
    assert refused(path, run) == (f"cannot resume from {path}: it is of format 'hivex-ppo/1', whose checksums do not "
                                  "cover its agent-steps and hyperparameters; it plays and evaluates, but a run goes on "
                                  "only from a checkpoint of format 'hivex-ppo/2': train again")
    flipped = copy.deepcopy(older)
    flip_bit(flipped["model"][WEIGHT], bit=3)
    assert refused(written(flipped, tmp_path / "flipped.pt"), run).endswith("its weights do not match their checksum")


def test_a_training_state_that_is_not_finite_is_refused(run, tmp_path, capsys):
    """Issue 54, item 12: a NaN Adam moment (checksummed as saved) killed training with torch's ``probability tensor
    contains either inf, nan or element < 0``."""
    data = copy.deepcopy(run["data"])
    state = data["training"]["optimizer"]["state"]
    first = next(iter(state))
    state[first]["exp_avg_sq"].view(-1)[0] = math.nan
    path = written(resealed(data), tmp_path / "c.pt")
    assert refused(path, run) == (f"{path} is corrupt: its training state's tensor "
                                  f"'optimizer.state.{first}.exp_avg_sq' holds NaN")


@pytest.mark.parametrize("field", REQUIRED)
def test_a_missing_field_is_named(field, run, tmp_path):
    path = written({k: v for k, v in run["data"].items() if k != field}, tmp_path / "c.pt")
    assert refused(path, run) == f"{path} is not a valid hivex checkpoint: it has no '{field}'"


@pytest.mark.parametrize("field,value", [(field, value) for field in (*REQUIRED, "wall_s", "training", "checksums")
                                         for value in RETYPES if (field, value) not in VALID_RETYPES])
def test_a_field_of_the_wrong_type_is_named(field, value, run, tmp_path):
    message = refused(written(run["data"] | {field: value}, tmp_path / "c.pt"), run)
    assert f"its '{field}' is " in message or (field, value) == ("training", None)  # then its checksum differs
    assert field in message


@pytest.mark.parametrize("field,value", [("model", None), ("config", [1]), ("agent_steps", "x")])
def test_the_evaluate_command_refuses_a_malformed_checkpoint_in_one_line(field, value, run, tmp_path, capsys):
    path = written(run["data"] | {field: value}, tmp_path / "c.pt")
    assert main(["evaluate", str(path), "--episodes", "1"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"hivex: {path} is not a valid hivex checkpoint: its '{field}' is ") and err.count("\n") == 1


@pytest.mark.parametrize("key,value,expected", [
    ("gamma", 1.5, "gamma: 1.5 is out of range: expected a number from 0.0 to 1.0"),
    ("hidden_units", "16", "hidden_units: expected an integer from 1 to 8192, got '16' (a string)"),
    ("num_layers", 0, "num_layers: 0 is out of range: expected an integer from 1 to 16"),
    ("learning_rate_schedule", "cosine", "learning_rate_schedule: 'cosine' is not allowed: expected"),
    ("curiosity_strength", "y", "curiosity_strength: expected a number from 0.0 to 1.0, got 'y' (a string)"),
    ("normalize", None, "normalize: expected true or false, got null"),
    ("device", "abacus", "device: 'abacus' is not allowed: expected cpu, cuda or cuda:N"),
    ("gama", 0.9, "unknown hyperparameter 'gama'; did you mean 'gamma'?"),
])
def test_a_bad_hyperparameter_is_named_with_what_was_expected(key, value, expected, run, tmp_path):
    data = copy.deepcopy(run["data"])
    data["config"][key] = value
    path = written(resealed(data), tmp_path / "c.pt")
    assert refused(path, run).startswith(f"{path} holds bad hyperparameters: {expected}")


def test_a_scenario_that_does_not_compile_is_named(run, tmp_path):
    data = copy.deepcopy(run["data"])
    data["scenario"]["agents"] = "9"
    path = written(resealed(data), tmp_path / "c.pt")
    assert refused(path, run) == (f"{path} holds a scenario that does not compile: agents: expected an integer "
                                  "from 9 to 9, got '9' (a string)")


def test_weights_that_are_not_tensors_or_do_not_fit_are_named(run, tmp_path):
    data = copy.deepcopy(run["data"])
    data["model"][WEIGHT] = data["model"][WEIGHT].tolist()
    path = written(data, tmp_path / "list.pt")
    assert refused(path, run) == (f"{path} is not a valid hivex checkpoint: its 'model.{WEIGHT}' is a list, "
                                  "expected a tensor")
    data["model"][WEIGHT] = torch.zeros(2)
    path = written(resealed(data), tmp_path / "small.pt")
    assert refused(path, run).startswith(f"{path}'s weights do not fit the network its own hyperparameters build: "
                                         f"Error(s) in loading state_dict for ActorCritic: size mismatch for {WEIGHT}")


@pytest.mark.parametrize("bad", [math.nan, math.inf])
def test_a_weight_that_is_not_finite_is_named(bad, run, tmp_path, capsys):
    """As a run that diverged would save it: the checksum matches the NaN."""
    data = copy.deepcopy(run["data"])
    data["model"][WEIGHT][0, 0] = bad
    path = written(resealed(data), tmp_path / "c.pt")
    what = "NaN" if math.isnan(bad) else "an infinite value"
    assert refused(path, run) == f"{path} is corrupt: its weight tensor '{WEIGHT}' holds {what}"
    assert main(["evaluate", str(path), "--episodes", "1"]) == 2
    assert capsys.readouterr().err == f"hivex: {path} is corrupt: its weight tensor '{WEIGHT}' holds {what}\n"


@pytest.mark.parametrize("bit", [0, 17, 31])
def test_one_flipped_bit_in_a_stored_weight_is_refused(bit, run, tmp_path, capsys):
    data = copy.deepcopy(run["data"])
    flip_bit(data["model"][WEIGHT], element=3, bit=bit)
    path = written(data, tmp_path / "c.pt")
    assert refused(path, run) == f"{path} is corrupt: its weights do not match their checksum"
    assert main(["evaluate", str(path), "--episodes", "1"]) == 2
    assert capsys.readouterr().err == f"hivex: {path} is corrupt: its weights do not match their checksum\n"


def test_one_flipped_bit_in_the_file_s_bytes_is_refused(run, tmp_path):
    """The bit flipped on disk, inside the tensor's stored bytes (torch's zip holds them uncompressed, unchecked)."""
    raw = bytearray(run["file"].read_bytes())
    at = raw.find(run["data"]["model"][WEIGHT].numpy().tobytes())
    assert at > 0
    raw[at + 5] ^= 0x10
    path = tmp_path / "c.pt"
    path.write_bytes(bytes(raw))
    assert refused(path, run) == f"{path} is corrupt: its weights do not match their checksum"


def test_one_flipped_bit_in_the_training_state_is_refused(run, tmp_path):
    data = copy.deepcopy(run["data"])
    moments = next(iter(data["training"]["optimizer"]["state"].values()))["exp_avg"]
    flip_bit(moments, bit=30)
    path = written(data, tmp_path / "c.pt")
    assert refused(path, run) == (f"{path} is corrupt: its training state (optimizers, curiosity module, curve) does "
                                  "not match its checksum")


@pytest.mark.parametrize("part", ["optimizer", "curiosity", "curiosity_optimizer", "curve"])
@pytest.mark.parametrize("value", ["removed", *RETYPES])
def test_a_training_state_that_is_missing_or_mistyped_is_named(part, value, run, tmp_path):
    data = copy.deepcopy(run["data"])
    if value == "removed":
        del data["training"][part]
    else:
        data["training"][part] = value
    path = written(resealed(data), tmp_path / "c.pt")
    message = refused(path, run)
    assert f"'training.{part}" in message or f"no {part} state" in message


def test_an_optimizer_state_of_other_shapes_cannot_resume(run, tmp_path):
    data = copy.deepcopy(run["data"])
    state = next(iter(data["training"]["optimizer"]["state"].values()))
    state["exp_avg"] = torch.zeros(3)
    path = written(resealed(data), tmp_path / "c.pt")
    assert refused(path, run).startswith(f"cannot resume from {path}: its optimizer state does not fit the run's: "
                                         "exp_avg of a parameter of shape")
    data["training"]["optimizer"]["param_groups"] = []
    path = written(resealed(data), tmp_path / "groups.pt")
    assert refused(path, run) == (f"cannot resume from {path}: its optimizer state does not fit the run's: loaded "
                                  "state dict has a different number of parameter groups")


def test_a_run_does_not_resume_from_a_checkpoint_that_lacks_its_curiosity_optimizer(run, tmp_path):
    folder = tmp_path / "run"
    train(run["compiled"], run["cfg"], folder, progress=False)
    data = torch.load(folder / "checkpoint.pt", weights_only=True)
    del data["training"]["curiosity_optimizer"]
    elsewhere = tmp_path / "copied"  # a folder of its own: in the run's, its manifest refuses the edited file first
    elsewhere.mkdir()
    written(resealed(data), elsewhere / "checkpoint.pt")
    with pytest.raises(TrainError, match=f"cannot resume from {elsewhere / 'checkpoint.pt'}: it holds no "
                                         "curiosity_optimizer state"):
        train(run["compiled"], run["cfg"], elsewhere, progress=False, resume=True)


def places(tree: Any, at: tuple = ()) -> list[tuple]:
    """The key path of every value in nested mappings and lists (the root excluded)."""
    children = (tree.items() if isinstance(tree, dict) else enumerate(tree) if isinstance(tree, (list, tuple))
                else ())
    found = []
    for key, child in children:
        found += [at + (key,), *places(child, at + (key,))]
    return found


def mutate(data: dict[str, Any], place: tuple, how: str, value: Any, bit: int) -> None:
    """Remove, retype, bit-flip or NaN the value at ``place`` of ``data``, in place."""
    *parent_keys, key = place
    parent = data
    for part in parent_keys:
        parent = parent[part]
    if isinstance(parent, tuple):  # Adam's betas: rebuild the tuple in its parent
        return mutate(data, tuple(parent_keys), "retype", [value if i == key else v for i, v in enumerate(parent)], 0)
    target = parent[key]
    if how == "flip" and isinstance(target, torch.Tensor) and target.numel():
        flip_bit(target, element=bit % target.numel(), bit=bit % (8 * target.element_size()))
    elif how == "nan" and isinstance(target, torch.Tensor) and target.is_floating_point() and target.numel():
        target.view(-1)[bit % target.numel()] = math.nan
    elif how == "remove":
        del parent[key]
    else:
        parent[key] = value


MUTATIONS = st.tuples(st.sampled_from(["remove", "retype", "flip", "nan"]),
                      st.sampled_from([*RETYPES, -1, 2.5, {}, True, math.nan, "", torch.zeros(2)]),
                      st.integers(0, 2**16), st.sampled_from(["as saved", "resealed", "dropped"]))


@settings(max_examples=FUZZ_CASES, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture,
                                                                         HealthCheck.too_slow])
@given(choice=st.data())
def test_random_mutations_are_accepted_or_refused_with_one_train_error(choice, run, tmp_path):
    data = copy.deepcopy(run["data"])
    all_places = places({k: v for k, v in data.items() if k != "checksums"})
    place = choice.draw(st.sampled_from(all_places), label="place")
    how, value, bit, seal = choice.draw(MUTATIONS, label="mutation")
    before = copy.deepcopy(data)
    mutate(data, place, how, value, bit)
    if seal == "resealed":
        data = resealed(data)
    elif seal == "dropped":
        data.pop("checksums")
    exc = refusal(written(data, tmp_path / "fuzzed.pt"), run)
    changed = checksum(sections(data)) != checksum(sections(before))
    if seal != "resealed" and changed:  # any change to any field, a flipped bit included
        assert exc is not None

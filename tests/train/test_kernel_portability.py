"""benchmarks/kernel_portability.py: merging machines' rows and telling which settings agree across them."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import yaml

import hivex_dsl

from .conftest import benchmark_script

script = benchmark_script("kernel_portability")
RESULTS = Path(__file__).resolve().parents[2] / "benchmarks" / "results" / "kernel_portability.json"
XEON = "Intel(R) Xeon(R) Processor family 6 model 207"
EPYC = "AMD EPYC family 25 model 17"
# AWS's rows of sessions 86-88, measured before session 89 changed its fire's defaults, kept as what they trained
AWS_BEFORE = RESULTS.parent / "kernel_portability_aerial_wildfire_suppression_before_session_89.json"
# AWS's rows of session 89, under the release's fire start and queue at a fire step every 17 steps (session 92 made
# the release's cadence and 3-D downwind angle the defaults)
AWS_BEFORE_92 = RESULTS.parent / "kernel_portability_aerial_wildfire_suppression_before_session_92.json"
# AWS's rows of session 92, under the shared weather (session 94 made the release's weather AWS's default)
AWS_BEFORE_94 = RESULTS.parent / "kernel_portability_aerial_wildfire_suppression_before_session_94.json"
# WRM's rows of sessions 81 and 88, with the agent's budget observed (session 95 made the fire's detection the default)
WRM_BEFORE_95 = RESULTS.parent / "kernel_portability_wildfire_resource_management_before_session_95.json"
# every file of rows measured under defaults since replaced, and the processor whose default trained its record
BEFORE_FILES = ((AWS_BEFORE, XEON), (AWS_BEFORE_92, EPYC), (AWS_BEFORE_94, EPYC), (WRM_BEFORE_95, XEON))


def cross_vendor_file(environment: str) -> Path:
    """The results file holding the Xeon's and the EPYC's rows of ``environment`` (one scenario's content)."""
    return {"aerial_wildfire_suppression": AWS_BEFORE,
            "wildfire_resource_management": WRM_BEFORE_95}.get(environment, script.results_file(environment))


def row_of(machines: dict[str, dict], processor: str) -> dict[str, list[float]]:
    """The one row of ``machines`` whose machine names ``processor``."""
    (row,) = [row for name, row in machines.items() if processor in name]
    return row


def test_a_machine_s_row_replaces_only_the_settings_it_measured():
    recorded = script.merge({}, "amd", {"default": [1.0, 2.0], "mkl-avx2": [1.0, 3.0]}, 2)
    recorded["notes"] = ["by hand"]
    recorded = script.merge(recorded, "xeon", {"default": [1.0, 2.5]}, 2)
    again = script.merge(recorded, "amd", {"mkl-avx2": [1.0, 4.0]}, 2)
    assert again["machines"] == {"amd": {"default": [1.0, 2.0], "mkl-avx2": [1.0, 4.0]}, "xeon": {"default": [1.0, 2.5]}}
    assert again["notes"] == ["by hand"]
    assert recorded["machines"]["amd"]["mkl-avx2"] == [1.0, 3.0]  # the file read is not changed in place


def test_rows_of_another_length_are_refused():
    recorded = script.merge({}, "amd", {"default": [1.0, 2.0]}, 2)
    with pytest.raises(ValueError, match="--points 2"):
        script.merge(recorded, "xeon", {"default": [1.0, 2.0, 3.0]}, 3)


def test_rows_of_another_scenario_are_refused_and_each_environment_has_its_file():
    recorded = script.merge({}, "amd", {"default": [1.0, 2.0]}, 2, "aerial_wildfire_suppression")
    assert recorded["scenario"] == "scenarios/aerial_wildfire_suppression/main.yaml"
    assert recorded["command"].startswith("hivex train scenarios/aerial_wildfire_suppression/main.yaml --seed 0")
    with pytest.raises(ValueError, match=r"write them to benchmarks/results/kernel_portability\.json"):
        script.merge(recorded, "xeon", {"default": [1.0, 2.0]}, 2, "wind_farm_control")
    assert script.results_file("wind_farm_control") == RESULTS
    aws = script.results_file("aerial_wildfire_suppression")
    assert aws.name == "kernel_portability_aerial_wildfire_suppression.json"


def test_rows_of_the_same_path_but_another_content_are_refused():
    """A default changed since a file's rows were measured: main.yaml trains something else under the same path."""
    recorded = script.merge({}, "amd", {"default": [1.0, 2.0]}, 2, fingerprint="sha256:then")
    assert recorded["fingerprint"] == "sha256:then"
    with pytest.raises(ValueError, match=r"fingerprint sha256:then.*\(sha256:now\): a default changed since"):
        script.merge(recorded, "xeon", {"default": [1.0, 2.0]}, 2, fingerprint="sha256:now")
    assert script.merge({}, "amd", {"default": [1.0]}, 1)["fingerprint"] == script.fingerprint_of("wind_farm_control")


def test_each_committed_file_names_the_content_its_rows_trained():
    """Every file of the scenario as it resolves now names its fingerprint and is set against the committed record;
    AWS's rows from before sessions 89, 92 and 94 and WRM's from before session 95 name the params and the weather
    then and keep the curve of the record they were measured against, whose seed 0 the default of the processor that
    trained it followed for all 40 points (the Xeon before session 89 and for WRM's, the AMD EPYC of family 25 model
    17 in sessions 89 and 92)."""
    for environment in ("wind_farm_control", "wildfire_resource_management", "drone_based_reforestation",
                        "aerial_wildfire_suppression"):
        recorded = json.loads(script.results_file(environment).read_text("utf-8"))
        assert recorded["fingerprint"] == script.fingerprint_of(environment)
        assert script.record_curve(recorded)[:3] == [round(point[2], 4) for point in json.loads(
            (RESULTS.parents[1] / "baselines" / f"{environment}.json").read_text("utf-8"))["curve"][:3]]
    fingerprints: dict[str, set[str]] = {}
    for path, trained_on in BEFORE_FILES:
        before = json.loads(path.read_text("utf-8"))
        fingerprints.setdefault(before["scenario"], set()).add(before["fingerprint"])
        scenario = yaml.safe_load((RESULTS.parents[2] / before["scenario"]).read_text("utf-8"))
        then = {**scenario, "params": before["params_then"], "generators": before["generators_then"]}
        assert hivex_dsl.compile(then).fingerprint == before["fingerprint"], path.name
        trained = row_of(before["machines"], trained_on)["default"]
        assert script.record_curve(before) == before["record_curve"] == trained
        without_its_curve = {key: value for key, value in before.items() if key != "record_curve"}
        assert script.record_curve(without_its_curve) is None  # the committed record is of another content now
    for environment, contents in (("aerial_wildfire_suppression", 4), ("wildfire_resource_management", 2)):
        then = fingerprints[script.scenario_of(environment)]
        assert len(then | {script.fingerprint_of(environment)}) == contents, environment


def test_machines_are_grouped_by_identical_returns_per_setting():
    recorded = {"points": 2, "machines": {
        "amd": {"default": [1.0, 2.0], "mkl-compatible": [1.0, 5.0]},
        "xeon": {"default": [1.0, 2.5], "mkl-compatible": [1.0, 5.0]},
        "epyc-2": {"default": [1.0, 2.0]}}}
    assert script.agreement(recorded) == {"default": [["amd", "epyc-2"], ["xeon"]],
                                          "mkl-compatible": [["amd", "xeon"]]}
    lines = script.report(recorded, record_curve=[1.0, 2.0, 7.0])
    assert lines[0] == "default: 2 different results on 3 machine(s)"
    assert lines[1] == "  [1.0, 2.0] (the committed record's curve): amd; epyc-2"
    assert lines[3] == "mkl-compatible: one result on 2 machine(s)"


def test_the_committed_file_holds_the_wfc_record_s_curve_under_the_default_of_some_machine():
    """The WFC main record (seed 0) reproduced to the digit on the AMD EPYCs of family 26 model 2 (session 63, its
    first 28 summary points) and family 25 model 17 (session 64, the 8 points measured); the Xeon of family 6 model
    167 leaves it at the sixth point (session 62)."""
    recorded = json.loads(RESULTS.read_text(encoding="utf-8"))
    record = json.loads((RESULTS.parents[1] / "baselines" / "wind_farm_control.json").read_text(encoding="utf-8"))
    curve = [round(point[2], 4) for point in record["curve"][:recorded["points"]]]
    defaults = {name: row["default"] for name, row in recorded["machines"].items() if "default" in row}
    assert sorted(name for name, returns in defaults.items() if returns == curve) == [
        f"x86_64, AMD EPYC family {kind}, torch's AVX512 kernels, 2 cores, Linux, Python 3.11.7"
        for kind in ("25 model 17", "26 model 2")]
    assert all(returns[:5] == curve[:5] for returns in defaults.values())  # the first 200,000 agent-steps agree


def test_the_committed_file_shows_mkl_s_compatible_path_agreeing_across_vendors():
    """Session 79 measured the Xeon of family 6 model 207 under every setting: under the default it gives the Xeon of
    model 167's returns (one vendor's alike processors agree), under MKL_CBWR=AVX2 its own, and under
    MKL_CBWR=COMPATIBLE (with or without ATen's default kernels) the AMD EPYCs' returns to the digit."""
    recorded = json.loads(RESULTS.read_text(encoding="utf-8"))
    groups = script.agreement(recorded)

    def vendors(group: list[str]) -> set[str]:
        return {"intel" if "Intel" in name else "amd" for name in group}

    for setting in ("mkl-compatible", "mkl-compatible-aten-default"):
        assert len(groups[setting]) == 1 and vendors(groups[setting][0]) == {"intel", "amd"}, setting
    assert sorted(tuple(vendors(group)) for group in groups["default"]) == [("amd",), ("intel",)]
    assert len(groups["mkl-avx2"]) == 2


def test_the_committed_file_shows_cpu_kernels_portable_training_alike_on_both_vendors():
    """Session 80: `hivex train --set cpu_kernels=portable` on the Intel Xeon of family 6 model 207, with no kernel
    variable in its environment, gives to the digit the returns both AMD EPYCs gave under the variables it stands for
    (MKL_CBWR=COMPATIBLE,STRICT and ATEN_CPU_CAPABILITY=default), and parts from the record's curve (the AMD EPYCs'
    default) where the Xeon's default does. Session 88: the AMD EPYC of family 25 model 17 trained under
    cpu_kernels portable itself gives the same returns, and NumPy's kernels of an AVX2-only processor change nothing
    there under either setting."""
    recorded = json.loads(RESULTS.read_text(encoding="utf-8"))
    assert recorded["settings"]["portable"] == {"arguments": "--set cpu_kernels=portable"}
    portable = {name: row["portable"] for name, row in recorded["machines"].items() if "portable" in row}
    assert {"Intel" in name for name in portable} == {True, False}
    amd = [row["mkl-compatible-aten-default"] for name, row in recorded["machines"].items() if "AMD" in name]
    assert len(amd) == 2 and all(returns == amd[0] for returns in [*amd, *portable.values()])
    assert all(recorded["machines"][name]["default"] != amd[0] for name in portable)
    (epyc,) = [row for name, row in recorded["machines"].items() if "numpy-avx2" in row]
    assert epyc["numpy-avx2"] == epyc["default"] and epyc["portable-numpy-avx2"] == epyc["portable"]


@pytest.mark.parametrize("environment, follows_record, portable_agrees", [
    ("aerial_wildfire_suppression", 40, 13),  # convolutions ('simple'): the record trained on this Xeon (session 86,
    # replaced in session 89: the rows of the fire before, AWS_BEFORE, keep its curve)
    ("drone_based_reforestation", 12, 14),  # ML-Agents' ResNet encoders: the record reproduced on an AMD EPYC
])
def test_a_convolutional_file_tells_the_kernels_apart_within_its_points(environment, follows_record, portable_agrees):
    """On the Xeon of family 6 model 207, over 40 points, the default follows the committed record for
    ``follows_record`` points (all 40 where the record trained on it) and cpu_kernels portable parts from the default
    after ``portable_agrees``: so the AMD EPYC's row (the test below) tells whether the portable convolution path is
    alike across vendors."""
    recorded = json.loads(cross_vendor_file(environment).read_text("utf-8"))
    assert recorded["scenario"] == script.scenario_of(environment) and recorded["points"] == 40
    curve = script.record_curve(recorded)[:40]
    xeon = row_of(recorded["machines"], XEON)
    default, portable = xeon["default"], xeon["portable"]
    assert default[:follows_record] == curve[:follows_record]
    assert follows_record == 40 or default[follows_record] != curve[follows_record]
    assert portable[:portable_agrees] == default[:portable_agrees]
    assert portable[portable_agrees] != default[portable_agrees]


@pytest.mark.parametrize("environment, defaults_part", [
    ("aerial_wildfire_suppression", 13),  # convolutions ('simple')
    ("drone_based_reforestation", 10),  # ML-Agents' ResNet encoders
])
def test_cpu_kernels_portable_trains_convolutions_alike_across_vendors(environment, defaults_part):
    """Session 88, the AMD EPYC of family 25 model 17 beside the Intel Xeon of family 6 model 207: under each one's
    native kernels the two part at the point of 0-based index ``defaults_part`` of 40; under cpu_kernels portable (no
    oneDNN: im2col and MKL's compatible products) they give the same returns at all 40 points, which differ from
    either's default."""
    recorded = json.loads(cross_vendor_file(environment).read_text("utf-8"))
    rows = recorded["machines"]
    xeon = row_of(rows, XEON)
    epyc = row_of(rows, EPYC)
    assert len(epyc["portable"]) == 40 and epyc["portable"] == xeon["portable"]
    assert epyc["default"][:defaults_part] == xeon["default"][:defaults_part]
    assert epyc["default"][defaults_part] != xeon["default"][defaults_part]
    assert epyc["portable"] != epyc["default"] and xeon["portable"] != xeon["default"]


def test_numpy_s_kernels_of_an_avx2_only_processor_train_wrm_alike():
    """Session 81, Wildfire Resource Management (whose power law took NumPy's processor-dependent pow until then):
    NumPy imitating an AVX2-only processor gives the processor's own returns under the default and under cpu_kernels
    portable, over 40 points; the default is the committed record's curve (trained on this Xeon) and portable parts
    from it, so the two settings are told apart within the points."""
    recorded = json.loads(WRM_BEFORE_95.read_text("utf-8"))
    assert recorded["points"] == 40
    assert recorded["settings"]["portable-numpy-avx2"] == {
        "NPY_DISABLE_CPU_FEATURES": "X86_V4 AVX512_ICL AVX512_SPR", "arguments": "--set cpu_kernels=portable"}
    xeon = row_of(recorded["machines"], XEON)
    assert xeon["numpy-avx2"] == xeon["default"] == script.record_curve(recorded)[:40]
    assert xeon["portable-numpy-avx2"] == xeon["portable"] != xeon["default"]


def test_wrm_trains_alike_across_vendors_under_cpu_kernels_portable_whatever_numpy_s_kernels():
    """Session 88, the AMD EPYC of family 25 model 17 beside the Xeon of family 6 model 207, Wildfire Resource
    Management's MLP over 40 points: portable (with NumPy's own kernels or an AVX2-only processor's) gives the
    Xeon's returns; the default follows the Xeon's (the committed record's curve) for 13 points and parts at the
    14th; NumPy's AVX2 kernels change nothing on the EPYC either."""
    rows = json.loads(WRM_BEFORE_95.read_text("utf-8"))["machines"]
    xeon = row_of(rows, XEON)
    epyc = row_of(rows, EPYC)
    assert epyc["portable"] == epyc["portable-numpy-avx2"] == xeon["portable"]
    assert epyc["numpy-avx2"] == epyc["default"]
    assert epyc["default"][:13] == xeon["default"][:13] and epyc["default"][13] != xeon["default"][13]


def test_wrm_follows_its_record_on_the_processor_that_trained_it():
    """Session 95, the scenario observing whether a fire is detected: on the AMD EPYC of family 25 model 17, which
    trained the record, the default kernels give the record's curve at all 40 points, with NumPy's own kernels or an
    AVX2-only processor's; cpu_kernels portable parts from them at the point of 0-based index 9."""
    recorded = json.loads(script.results_file("wildfire_resource_management").read_text("utf-8"))
    assert recorded["points"] == 40 and "record_curve" not in recorded
    epyc = row_of(recorded["machines"], EPYC)
    assert epyc["default"] == epyc["numpy-avx2"] == script.record_curve(recorded)[:40]
    assert epyc["portable"] == epyc["portable-numpy-avx2"]
    assert epyc["portable"][:9] == epyc["default"][:9] and epyc["portable"][9] != epyc["default"][9]


@pytest.mark.parametrize("results, portable_parts_at", [
    (AWS_BEFORE_92, 6),  # session 89: the release's fire start and burning queue at a fire step every 17 steps
    (AWS_BEFORE_94, 24),  # session 92: the release's fire cadence and 3-D downwind angle, the shared weather
    (script.results_file("aerial_wildfire_suppression"), 17),  # session 94: the release's weather, the defaults now
])
def test_aws_follows_its_record_on_the_processor_that_trained_it(results, portable_parts_at):
    """Each AWS scenario whose record the AMD EPYC of family 25 model 17 trained (sessions 89, 91 and 93): on that
    processor the default kernels give the record's curve at all 40 points, and cpu_kernels portable parts from them
    at the point of 0-based index ``portable_parts_at``. The rows of a scenario since replaced keep the curve of the
    record they were measured against (``record_curve``); the file of the defaults now reads the committed record."""
    recorded = json.loads(results.read_text("utf-8"))
    assert recorded["points"] == 40
    assert ("record_curve" in recorded) == (results != script.results_file("aerial_wildfire_suppression"))
    epyc = row_of(recorded["machines"], EPYC)
    assert epyc["default"] == script.record_curve(recorded)[:40]
    at = portable_parts_at
    assert epyc["portable"][:at] == epyc["default"][:at] and epyc["portable"][at] != epyc["default"][at]


def test_numpy_s_avx2_kernels_train_aws_as_its_own_on_the_epyc():
    """Session 94, the scenario under the release's weather: NumPy imitating an AVX2-only processor (the island's
    noise, the fire, the planes) gives the EPYC's own returns under the default kernels and under cpu_kernels portable
    at all 40 points: NumPy's kernel choice alone does not part an AWS run on an AVX2-only processor."""
    recorded = json.loads(script.results_file("aerial_wildfire_suppression").read_text("utf-8"))
    epyc = row_of(recorded["machines"], EPYC)
    assert len(epyc["numpy-avx2"]) == 40
    assert epyc["numpy-avx2"] == epyc["default"] and epyc["portable-numpy-avx2"] == epyc["portable"]

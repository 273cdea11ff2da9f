"""hivex_dsl.base.portable, and every environment computing the same bits whatever vector kernels NumPy takes.

NumPy picks the kernels of exp, log, arctan2 and ** by processor: its own AVX-512 ones where the processor has them,
libm's elsewhere, and the two differ in the last bit of some results. A Wildfire Resource Management tower's
performance (a broken power law) did so from its eighth decision, so an AVX2-only processor and an AVX-512 one logged
different rewards and statistics from the same seed, even under ``cpu_kernels portable`` (a training run kept its
first 40 points, float32 dropping those bits: benchmarks/results/kernel_portability_wildfire_resource_management.json),
and the scripted policies took other decisions. NumPy's NPY_DISABLE_CPU_FEATURES imitates
an AVX2-only processor (X86_V4 and the AVX-512 groups above it off) and one with SSE4.2 alone (X86_V3 off as well)
in a fresh Python; tests/portable_digests.py computes what each environment and function gives there.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from hivex_dsl.base import portable
from hivex_dsl.compiler import registry

ROOT = Path(__file__).resolve().parents[1]
IMITATED = {"AVX2 alone": portable.AVX512_GROUPS, "SSE4.2 alone": ("X86_V3",) + portable.AVX512_GROUPS}


def test_each_function_is_libm_s():
    rng = np.random.default_rng(1)
    x, y = rng.uniform(-5.0, 5.0, 2000), rng.uniform(-5.0, 5.0, 2000)
    x[:8] = [0.0, -0.0, 0.0, -0.0, np.inf, -np.inf, 1.0, -1.0]  # signed zeros and infinities: atan2's quadrants
    y[:8] = [0.0, 0.0, -0.0, -0.0, 1.0, 1.0, np.inf, -np.inf]
    assert [float(v) for v in portable.arctan2(y, x)] == [math.atan2(b, a) for a, b in zip(x, y)]
    assert [float(v) for v in portable.exp(x[8:])] == [math.exp(a) for a in x[8:]]
    base = np.abs(x[8:]) + 0.01
    assert [float(v) for v in portable.power(base, 5.0)] == [math.pow(a, 5.0) for a in base]
    assert [float(v) for v in portable.power(base, y[8:])] == [math.pow(a, b) for a, b in zip(base, y[8:])]


def test_exact_exponents_are_numpy_s_own():
    """NumPy's reciprocal, square root and square are exact everywhere: a terrain's t ** 2 keeps its bits."""
    t = np.random.default_rng(2).uniform(0.0, 3.0, 500)
    for exponent in portable.EXACT_EXPONENTS:
        assert np.array_equal(portable.power(t, exponent), t ** exponent)
    assert portable.power(t, 2).tobytes() == (t * t).tobytes()


def test_the_edges_are_numpy_s():
    with np.errstate(over="ignore"):
        assert portable.exp(np.array([1000.0, -1000.0, 0.0])).tolist() == [np.inf, 0.0, 1.0]
    assert portable.log(np.array([0.0, 1.0, np.inf])).tolist() == [-np.inf, 0.0, np.inf]
    assert np.isnan(portable.log(np.array([-1.0, np.nan]))).all()
    values = np.random.default_rng(3).uniform(1e-6, 1e6, 1000)
    assert np.allclose(portable.log(values), np.log(values), rtol=3e-16, atol=0.0)
    assert portable.arctan2(1.0, 0.0).shape == () and portable.arctan2(np.zeros((2, 3)), 1.0).shape == (2, 3)


def _cpu_features() -> dict[str, bool]:
    from numpy._core._multiarray_umath import __cpu_features__

    return __cpu_features__


def _digests(disabled: tuple[str, ...], environments: list[str]) -> dict[str, str]:
    present = [name for name in disabled if _cpu_features().get(name)]  # NumPy refuses to disable what is absent
    env = {**os.environ, "NPY_DISABLE_CPU_FEATURES": " ".join(present), "OMP_NUM_THREADS": "1"}
    done = subprocess.run([sys.executable, str(ROOT / "tests" / "portable_digests.py"), *environments], cwd=ROOT,
                          env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-3000:]
    return json.loads(done.stdout.splitlines()[-1])


@pytest.fixture(scope="module")
def native_digests():
    if not _cpu_features().get("AVX512F"):
        pytest.skip("this processor has no AVX-512: NumPy takes the kernels an imitated one would, nothing differs")
    return _digests((), list(registry.environments()))


@pytest.mark.parametrize("imitated", IMITATED)
def test_an_imitated_processor_computes_every_environment_alike(native_digests, imitated):
    there = _digests(IMITATED[imitated], list(registry.environments()))
    numpy_own = [name for name in there if name.startswith("numpy ")]
    # the imitation bites: NumPy's own functions give other bits there, so alike environments are not a tautology
    assert [name for name in numpy_own if there[name] != native_digests[name]] == numpy_own
    assert {name: there[name] for name in there if name not in numpy_own} == \
        {name: native_digests[name] for name in there if name not in numpy_own}

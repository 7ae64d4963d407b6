"""Every keyword argument refuses what is not a value of its kind: None where None
does not mean "not given", bytes for str, NUL characters, arrays for numbers, bool for
numbers, integers beyond int, NaN and infinity, each with a message naming the keyword and
what it accepts (the command line's message where the library checks the range)."""
import math
import os
import subprocess
import sys

import numpy as np
import pytest

import cmcsurf

N = 16


@pytest.fixture(scope="module")
def phi():
    return cmcsurf.initial_field("G", N)


@pytest.fixture(scope="module")
def small_result():
    return cmcsurf.run("G", 0.5, N, 0.05, max_steps=2, threads=1)


def message(error, call):
    with pytest.raises(error) as e:
        call()
    return str(e.value)


@pytest.mark.parametrize("kwargs,error,text", [
    # None runs no default: it is refused where it does not mean "not given".
    ({"surface": None}, TypeError,
     "surface: got None of type NoneType; accepted: a string"),
    ({"stop": None}, TypeError, "stop: got None of type NoneType; accepted: a string"),
    ({"max_steps": None}, TypeError,
     "max_steps: got None of type NoneType; accepted: an integer"),
    ({"epsilon": None}, TypeError,
     "epsilon: got None of type NoneType; accepted: a real number"),
    ({"paper": None}, TypeError, "paper: got None; accepted: True or False"),
    ({"seed": None}, TypeError, "seed: got None of type NoneType; accepted: an integer"),
    ({"threads": None}, TypeError,
     "threads: got None of type NoneType; accepted: an integer"),
    # bytes are not str.
    ({"surface": b"G"}, TypeError, "surface: got b'G' of type bytes; accepted: a string"),
    ({"smoother": b"lex"}, TypeError,
     "smoother: got b'lex' of type bytes; accepted: a string"),
    # A NUL would cut the string short.
    ({"surface": "expr:sin(x)\x00garbage"}, ValueError,
     "surface: got 'expr:sin(x)\\x00garbage', which holds a NUL character; accepted: a string "
     "without NUL characters"),
    # An array of one element is no number.
    ({"epsilon": np.array([0.01])}, TypeError,
     "epsilon: got array([0.01]) of type ndarray; accepted: a real number"),
    ({"epsilon": np.array(0.01)}, TypeError,
     "epsilon: got array(0.01) of type ndarray; accepted: a real number"),
    ({"grid": np.array([16])}, TypeError,
     "grid: got array([16]) of type ndarray; accepted: an integer"),
    ({"seed": np.array([3])}, TypeError,
     "seed: got array([3]) of type ndarray; accepted: an integer"),
    # bool is not a number.
    ({"grid": True}, TypeError, "grid: got True of type bool; accepted: an integer"),
    ({"epsilon": True}, TypeError, "epsilon: got True of type bool; accepted: a real number"),
    ({"seed": False}, TypeError, "seed: got False of type bool; accepted: an integer"),
    ({"threads": True}, TypeError, "threads: got True of type bool; accepted: an integer"),
    ({"max_steps": np.bool_(True)}, TypeError,
     "max_steps: got True of type bool_; accepted: an integer"),
    # Integers beyond int: the library's range with the value given.
    ({"grid": 2**40}, ValueError, "--grid: got 1099511627776; accepted: N <= 2048"),
    ({"grid": -2**40}, ValueError,
     "--grid: must be m * 2^k with m in {1, 3, 5, 7}, k >= 2 and N >= 8 so that multigrid can "
     "coarsen it; got -1099511627776 (nearest accepted: 8)"),
    ({"pre_sweeps": 2**40}, ValueError, "--pre-sweeps: got 1099511627776; accepted: 0..50"),
    ({"coarse_levels": 2**70}, ValueError,
     "--coarse-levels: got 1180591620717411303424; accepted: 0..4"),
    ({"max_steps": 2**40}, ValueError,
     "max_steps: got 1099511627776; accepted: an int (|n| < 2^31) in the range of its option "
     "(`cmcsurf run --help`)"),
    ({"threads": 2**70}, ValueError,
     "--threads: got 1180591620717411303424; accepted: 0 <= T <= 4096 (0: OMP_NUM_THREADS or "
     "all cores)"),
    ({"seed": 2**64}, ValueError, "--seed: got 18446744073709551616; accepted: 0 <= S < 2^64"),
    ({"seed": -2**70}, ValueError,
     "--seed: got -1180591620717411303424; accepted: 0 <= S < 2^64"),
    # NaN, infinity and floats beyond double where a finite number is required.
    ({"epsilon": math.nan}, ValueError, "--epsilon: got nan; accepted: 0 < E < 1"),
    ({"dt_factor": math.inf}, ValueError, "--dt-factor: got inf; accepted: C > 0 (dt = C h)"),
    ({"tol": math.nan}, ValueError, "--tol: got nan; accepted: T > 0"),
    ({"mg_rtol": math.nan}, ValueError, "--mg-rtol: got nan; accepted: 0 <= R < 1"),
    ({"dt_max_factor": math.inf}, ValueError, "--dt-max-factor: got inf; accepted: 0 (fixed "
     "dt) or --dt-factor <= F <= 1000"),
    ({"epsilon": 10**400}, ValueError, "--epsilon: got inf; accepted: 0 < E < 1"),
    ({"volume_fraction": np.float64(-math.inf)}, ValueError,
     "--volume-fraction: got -inf; accepted: 0 < A < 1"),
])
def test_run_refuses(kwargs, error, text):
    assert message(error, lambda: cmcsurf.run(**{"grid": N, "max_steps": 1, **kwargs})) == text


def test_none_still_means_not_given_where_fast_chooses():
    r = cmcsurf.run("G", 0.5, N, 0.05, max_steps=1, fast=True, mg_rtol=None, extrapolate=None,
                    coarse_levels=None, threads=1)
    assert r.report["parameters"]["mg_rtol"] == 1e-2


def test_the_other_functions_refuse_the_same(phi, small_result, tmp_path):
    for call, error, text in [
        (lambda: cmcsurf.relax(phi, algorithm=b"cmc"), TypeError,
         "algorithm: got b'cmc' of type bytes; accepted: a string"),
        (lambda: cmcsurf.relax(phi, algorithm=None), TypeError,
         "algorithm: got None of type NoneType; accepted: a string"),
        (lambda: cmcsurf.relax(phi, volume_fraction=np.array([0.3])), TypeError,
         "volume_fraction: got array([0.3]) of type ndarray; accepted: a real number"),
        (lambda: cmcsurf.relax(phi, volume_fraction=True), TypeError,
         "volume_fraction: got True of type bool; accepted: a real number"),
        (lambda: cmcsurf.relax(phi, max_vcycles=2**40), ValueError,
         "max_vcycles: got 1099511627776; accepted: an int (|n| < 2^31) in the range of its "
         "option (`cmcsurf run --help`)"),
        (lambda: cmcsurf.measure(phi, epsilon=None), TypeError,
         "epsilon: got None of type NoneType; accepted: a real number"),
        (lambda: cmcsurf.measure(phi, surface=b"G"), TypeError,
         "surface: got b'G' of type bytes; accepted: a string"),
        (lambda: cmcsurf.measure(phi, epsilon=math.nan), ValueError,
         "--epsilon: got nan; accepted: 0 < E < 1"),
        (lambda: cmcsurf.initial_field(None, N), TypeError,
         "surface: got None of type NoneType; accepted: a string"),
        (lambda: cmcsurf.initial_field("G", 2**40), ValueError,
         "--grid: got 1099511627776; accepted: N <= 2048"),
        (lambda: cmcsurf.initial_field("sphere", N, radius=np.array([0.2])), TypeError,
         "radius: got array([0.2]) of type ndarray; accepted: a real number"),
        (lambda: cmcsurf.sweep(None, (0.5,), grid=N), TypeError,
         "surfaces: got None of type NoneType; accepted: a str \"P,D,G\" or a sequence of str"),
        (lambda: cmcsurf.sweep(b"G", (0.5,), grid=N), TypeError,
         "surfaces: got b'G' of type bytes; accepted: a str \"P,D,G\" or a sequence of str"),
        (lambda: cmcsurf.sweep(("G", b"P"), (0.5,), grid=N), TypeError,
         "surfaces[1]: got b'P' of type bytes; accepted: a string"),
        (lambda: cmcsurf.sweep("G\x00,P", (0.5,), grid=N), ValueError,
         "surfaces: got 'G\\x00,P', which holds a NUL character; accepted: a string without "
         "NUL characters"),
        (lambda: cmcsurf.sweep(("G",), None, grid=N), TypeError,
         "volume_fractions: got None of type NoneType; accepted: a str \"start:stop:step\" or "
         "\"a,b,c\", or a sequence of real numbers"),
        (lambda: cmcsurf.sweep(("G",), (0.5, True), grid=N), TypeError,
         "volume_fractions[1]: got True of type bool; accepted: a real number"),
        (lambda: cmcsurf.sweep(("G",), ("0.5",), grid=N), TypeError,
         "volume_fractions[0]: got '0.5' of type str; accepted: a real number"),
        (lambda: cmcsurf.sweep(("G",), (0.5,), grid=N, continuation=None), TypeError,
         "continuation: got None; accepted: True or False"),
        (lambda: cmcsurf.mesh(phi, solid=None), TypeError,
         "solid: got None of type NoneType; accepted: a string"),
        (lambda: cmcsurf.mesh(phi, units=b"mm"), TypeError,
         "units: got b'mm' of type bytes; accepted: a string"),
        (lambda: cmcsurf.mesh(phi, cell_size=np.array([1.0])), TypeError,
         "cell_size: got array([1.]) of type ndarray; accepted: a real number"),
        (lambda: cmcsurf.mesh(phi, cell_size=True), TypeError,
         "cell_size: got True of type bool; accepted: a real number"),
        (lambda: cmcsurf.mesh(phi, cell_size=math.inf), ValueError,
         "--cell-size: got inf; accepted: 0.001 .. 1e+06"),
        (lambda: cmcsurf.mesh(phi, threads=2**70), ValueError,
         "--threads: got 1180591620717411303424; accepted: 0 <= T <= 4096 (0: OMP_NUM_THREADS "
         "or all cores)"),
        (lambda: small_result.save(None), TypeError,
         "dir: got None of type NoneType; accepted: a str or os.PathLike path"),
        (lambda: small_result.save(str(tmp_path / "a\x00b")), ValueError,
         "which holds a NUL character"),
        (lambda: small_result.save(tmp_path / "r", float32=None), TypeError,
         "float32: got None; accepted: True or False"),
        (lambda: cmcsurf.mesh(phi).save(tmp_path / "m.stl", format=b"stl"), TypeError,
         "format: got b'stl' of type bytes; accepted: a string"),
        (lambda: cmcsurf.mesh(phi).save(b"m.stl"), TypeError,
         "path: got b'm.stl' of type bytes; accepted: a str or os.PathLike path"),
    ]:
        assert text in message(error, call)
    assert not list(tmp_path.iterdir())  # nothing written


def test_sequences_and_numpy_values_are_accepted(tmp_path, small_result):
    results, _ = cmcsurf.sweep(["G"], np.array([0.5]), grid=N, epsilon=0.05, max_steps=1,
                               threads=1)
    assert [r.report["member"] for r in results] == ["G_0.50"]
    assert small_result.save(tmp_path / "r", preview=np.bool_(False), report=False).is_dir()


@pytest.mark.parametrize("value,ok", [("100000", False), ("0", False), ("abc", False),
                                      ("4,", False), ("", False), ("2", True), ("4,2", True)])
def test_import_checks_omp_num_threads(value, ok):
    """OpenMP would start OMP_NUM_THREADS threads at the first parallel region (100000: a
    crash), also in Result.save, which takes no threads=: refused at import, as by the CLI."""
    child = subprocess.run([sys.executable, "-c", "import cmcsurf"], capture_output=True,
                           text=True, env=dict(os.environ, OMP_NUM_THREADS=value))
    if ok:
        assert child.returncode == 0, child.stderr
    else:
        assert child.returncode != 0
        assert (f"ImportError: OMP_NUM_THREADS: got '{value}'; accepted: 1 <= T <= 4096"
                in child.stderr), child.stderr

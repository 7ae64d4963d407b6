"""Arrays in and out: index order, conversion, relax() against run(), refused input."""
import numpy as np
import pytest

import cmcsurf
from conftest import comparable, run_cli

N = 16


@pytest.fixture(scope="module")
def x_field():
    """phi^0 of a formula of x alone: varies along axis 0 only."""
    return cmcsurf.initial_field("expr:sin(x)", grid=N)


def test_index_order_is_x_y_z(x_field):
    phi = x_field
    assert phi.shape == (N, N, N)
    # Constant over j and k (y and z), varying along i (x).
    assert np.all(phi == phi[:, :1, :1])
    assert np.ptp(phi[:, 0, 0]) > 0.5
    # sin peaks at x = pi / 2, i.e. cell i = N / 4 - 1/2, and is lowest at 3 N / 4 - 1/2.
    i = np.arange(N)
    assert abs(np.argmax(phi[:, 0, 0]) - (N / 4 - 0.5)) <= 0.5
    assert abs(np.argmin(phi[:, 0, 0]) - (3 * N / 4 - 0.5)) <= 0.5
    del i


def test_mesh_coordinates_follow_the_array_axes(x_field):
    m = cmcsurf.mesh(x_field, solid="surface")
    v = m.vertices
    # The phi = 1/2 surface of a field of x alone: planes x = const.
    assert len(np.unique(np.round(v[:, 0], 9))) <= 2
    assert len(np.unique(np.round(v[:, 1], 9))) > N // 2


def test_any_real_dtype_and_strides_give_the_same_field(x_field):
    def measure(phi):
        return comparable(cmcsurf.measure(phi, 0.05, threads=1))
    ref = measure(x_field)
    fortran = np.asfortranarray(x_field)
    strided = np.zeros((N, 2 * N, N))[:, ::2, :]
    strided[...] = x_field
    for variant in (fortran, strided, x_field.tolist()):
        assert measure(variant) == ref
    as32 = x_field.astype(np.float32)
    assert measure(as32) == measure(as32.astype(np.float64))
    # A 0/1 integer field (a segmented volume) is accepted and left unchanged.
    seg = (x_field > 0.5).astype(np.int32)
    before = seg.copy()
    assert 0.3 < cmcsurf.measure(seg, 0.05)["volume_fraction"] < 0.7
    assert np.array_equal(seg, before)


def test_transposed_field_is_not_the_same_field(x_field):
    a = cmcsurf.mesh(x_field, solid="surface").vertices
    b = cmcsurf.mesh(np.ascontiguousarray(x_field.transpose(1, 0, 2)), solid="surface").vertices
    assert len(np.unique(np.round(b[:, 1], 9))) <= 2  # the planes are now y = const
    assert not np.array_equal(a, b)


def test_relax_of_step_1_field_equals_run_for_a_direct_relaxation():
    # Section 4.1's spinodal decomposition from noise: run() relaxes it directly.
    phi0 = cmcsurf.initial_field("noise", N, 0.05)
    run = cmcsurf.run("noise", grid=N, epsilon=0.05, threads=1)
    rel = cmcsurf.relax(phi0, epsilon=0.05, prerelax_steps=5, surface="noise",
                        algorithm="direct", threads=1)
    assert np.array_equal(rel.phi, run.phi)
    assert comparable(rel.report) == comparable(run.report)
    assert run.report["area"] > 1.0 and run.report["converged"]


def test_relax_of_a_nodal_field_equals_run():
    # epsilon 0.03: at 0.05 on 16^3 this gyroid dissolves into one phase (no surface: an error)
    phi0 = cmcsurf.initial_field("G", N, 0.03)
    run = cmcsurf.run("G", 0.3, N, epsilon=0.03, threads=1)
    rel = cmcsurf.relax(phi0, 0.3, epsilon=0.03, prerelax_steps=5, surface="G", threads=1)
    assert np.array_equal(rel.phi, run.phi)
    assert comparable(rel.report) == comparable(run.report)
    assert run.report["volume_corrections"] >= 1  # the whole algorithm ran, constraint too


def test_relax_holds_the_own_volume_fraction_by_default(x_field):
    own = cmcsurf.measure(x_field, 0.05)["volume_fraction"]
    r = cmcsurf.relax(x_field, epsilon=0.05, threads=1)
    assert r.report["surface"] == "field" and r.report["volume_fraction_target"] == own
    assert abs(r.report["volume_fraction"] - own) <= r.report["parameters"]["volume_tol"]


def test_direct_relax_keeps_the_mass(x_field):
    r = cmcsurf.relax(x_field, epsilon=0.05, max_steps=5, algorithm="direct", threads=1)
    assert r.report["steps"] == 5 and r.report["volume_fraction_target"] is None
    assert abs(r.phi.mean() - x_field.mean()) < 1e-10
    with pytest.raises(ValueError, match="volume_fraction"):
        cmcsurf.relax(x_field, 0.4, algorithm="direct")
    with pytest.raises(ValueError, match="algorithm"):
        cmcsurf.relax(x_field, algorithm="fast")
    with pytest.raises(ValueError, match="--volume-fraction"):
        cmcsurf.relax(x_field, 1.5)
    with pytest.raises(ValueError, match="both phases"):
        cmcsurf.relax(np.zeros((N, N, N)))


BAD_ARRAYS = [
    (np.zeros((16, 16, 8)), ValueError, "cubic"),
    (np.zeros((16, 16)), ValueError, "cubic"),
    (np.zeros((50, 50, 50)), ValueError, "48 or 56"),
    (np.zeros((4, 4, 4)), ValueError, "phi"),
    (np.full((16, 16, 16), np.nan), ValueError, "finite"),
    (np.zeros((16, 16, 16), dtype=complex), TypeError, "dtype"),
    (np.zeros((16, 16, 16), dtype=bool), TypeError, "dtype"),
    ("abc", TypeError, "dtype"),
]


@pytest.mark.parametrize("phi,error,words", BAD_ARRAYS)
def test_bad_arrays_are_refused_naming_phi(phi, error, words):
    for call in (lambda: cmcsurf.measure(phi), lambda: cmcsurf.relax(phi),
                 lambda: cmcsurf.mesh(phi)):
        with pytest.raises(error) as e:
            call()
        assert str(e.value).startswith("phi:") and words in str(e.value)


def test_inf_is_named_with_its_index():
    phi = np.zeros((16, 16, 16))
    phi[3, 4, 5] = np.inf
    with pytest.raises(ValueError, match=r"phi: inf at \[3, 4, 5\]"):
        cmcsurf.measure(phi)


@pytest.mark.parametrize("args,option", [
    (["--grid", "50"], "grid"), (["--volume-fraction", "1.2"], "volume_fraction"),
    (["--epsilon", "0"], "epsilon"), (["--surface", "Q"], "surface"),
    (["--stop", "energy"], "stop"), (["--smoother", "jacobi"], "smoother"),
    (["--constrain", "area"], "constrain"), (["--max-steps", "0"], "max_steps"),
    (["--dt-max-factor", "0.25"], "dt_max_factor"),
])
def test_bad_options_raise_the_cli_message(args, option):
    cli = run_cli("run", *args, "--out", "/nonexistent/never-written", check=False)
    assert cli.returncode == 2
    message = cli.stderr.strip().removeprefix("error: ")
    value = args[1]
    kwargs = {option: value if option in ("surface", "stop", "smoother", "constrain")
              else (int(value) if option in ("grid", "max_steps") else float(value))}
    with pytest.raises(ValueError) as e:
        cmcsurf.run(**kwargs)
    assert str(e.value) == message


@pytest.mark.parametrize("kwargs,error,words", [
    ({"grid": 32.5}, TypeError, "grid"),
    ({"grid": "32"}, TypeError, "grid"),
    ({"epsilon": "small"}, TypeError, "epsilon"),
    ({"fast": 1}, TypeError, "fast"),
    ({"bogus": 1}, TypeError, "bogus"),
    ({"progress": 5}, TypeError, "progress"),
])
def test_bad_types_raise(kwargs, error, words):
    with pytest.raises(error, match=words):
        cmcsurf.run(**kwargs)


def test_relax_refuses_coarse_levels(x_field):
    with pytest.raises(ValueError, match="--coarse-levels"):
        cmcsurf.relax(x_field, coarse_levels=1)


@pytest.mark.parametrize("args,kwargs", [
    (["--threads", "-1"], {"threads": -1}),
    (["--threads", "5000"], {"threads": 5000}),
    (["--surface", "noise", "--seed", "-1"], {"surface": "noise", "seed": -1}),
    (["--epsilon", "0"], {"epsilon": 0.0}),
    (["--epsilon", "1.5"], {"epsilon": 1.5}),
])
def test_threads_seed_epsilon_messages_are_the_cli_messages(args, kwargs):
    cli = run_cli("run", *args, "--out", "/nonexistent/never-written", check=False)
    assert cli.returncode == 2
    message = cli.stderr.strip().splitlines()[0].removeprefix("error: ")
    with pytest.raises(ValueError) as e:
        cmcsurf.run(**kwargs)
    assert str(e.value) == message
    # The same checks behind measure(), relax(), sweep() and mesh() (threads, epsilon).
    phi = cmcsurf.initial_field("G", N)
    calls = []
    if "threads" in kwargs:
        calls = [lambda: cmcsurf.measure(phi, threads=kwargs["threads"]),
                 lambda: cmcsurf.relax(phi, threads=kwargs["threads"]),
                 lambda: cmcsurf.sweep(("G",), (0.5,), grid=N, threads=kwargs["threads"]),
                 lambda: cmcsurf.mesh(phi, threads=kwargs["threads"])]
    if "epsilon" in kwargs:
        calls = [lambda: cmcsurf.measure(phi, epsilon=kwargs["epsilon"]),
                 lambda: cmcsurf.relax(phi, epsilon=kwargs["epsilon"])]
    for call in calls:
        with pytest.raises(ValueError) as e:
            call()
        assert str(e.value) == message


def test_wrong_types_raise_type_error_with_the_wording_of_run():
    phi = cmcsurf.initial_field("G", N)
    with pytest.raises(TypeError) as e:
        cmcsurf.run(epsilon="0.05")
    wording = str(e.value)
    assert wording == "epsilon: got '0.05' of type str; accepted: a real number"
    for call, text in [
        (lambda: cmcsurf.measure(phi, epsilon="0.05"), wording),
        (lambda: cmcsurf.relax(phi, epsilon="0.05"), wording),
        (lambda: cmcsurf.relax(phi, volume_fraction="x"),
         "volume_fraction: got 'x' of type str; accepted: a real number"),
        (lambda: cmcsurf.mesh(phi, cell_size="2"),
         "cell_size: got '2' of type str; accepted: a real number"),
        (lambda: cmcsurf.run(threads=1.5), "threads: got 1.5 of type float; accepted: an integer"),
        (lambda: cmcsurf.measure(phi, threads=1.5),
         "threads: got 1.5 of type float; accepted: an integer"),
        (lambda: cmcsurf.mesh(phi, threads="2"),
         "threads: got '2' of type str; accepted: an integer"),
        (lambda: cmcsurf.run(seed=1.0), "seed: got 1.0 of type float; accepted: an integer"),
        (lambda: cmcsurf.run(volume_fraction="0.3"),
         "volume_fraction: got '0.3' of type str; accepted: a real number"),
        (lambda: cmcsurf.sweep(("G",), (0.5,), grid=N, continuation=1),
         "continuation: got 1; accepted: True or False"),
    ]:
        with pytest.raises(TypeError) as e:
            call()
        assert str(e.value) == text


def test_numpy_scalars_are_accepted_as_numbers():
    r = cmcsurf.run("sphere", grid=np.int64(N), epsilon=np.float32(0.05), seed=np.uint8(3),
                    max_steps=2, threads=np.int32(1))
    assert r.report["grid"] == N and r.report["parameters"]["seed"] == 3

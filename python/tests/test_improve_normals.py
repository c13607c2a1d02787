"""pnf.improve_normals: the CLI's answer, any input layout, no copies, progress and cancel."""

from __future__ import annotations

import subprocess
import sys
import textwrap
import tracemalloc

import numpy as np
import pytest

import pnf
from conftest import angles_deg, noisy_cube

# The module and the CLI run the same library code on the same double values, so they agree to
# rounding; 1e-4 degrees is the bound.
kCliToleranceDeg = 1e-4


def test_returns_unit_float64_normals_closer_to_the_truth(cube, backend):
    points, normals, truth = cube
    out = pnf.improve_normals(points, normals, backend=backend)
    assert out.shape == points.shape and out.dtype == np.float64 and out.flags.c_contiguous
    np.testing.assert_allclose(np.linalg.norm(out, axis=1), 1.0, atol=1e-6)
    assert angles_deg(out, truth).mean() < 0.5 * angles_deg(normals, truth).mean()


@pytest.mark.parametrize("extra", [[], ["--sigma-f", "3", "--sigma-g", "0.3", "--iterations", "2"], ["--auto"]])
def test_equals_the_cli(cube, backend, cli, tmp_path, extra):
    points, normals, _ = cube
    source, target = tmp_path / "in.ply", tmp_path / "out.ply"
    pnf.write(source, points, normals)  # double x y z nx ny nz: the CLI reads the same values
    subprocess.run([str(cli), "filter", str(source), str(target), "--backend", backend, "--quiet", *extra],
                   check=True)
    from_cli = pnf.read(target).normals
    kwargs = {"auto": True} if extra == ["--auto"] else {}
    if extra and not kwargs:
        kwargs = {"sigma_f": 3.0, "sigma_g": 0.3, "iterations": 2}
    from_module = pnf.improve_normals(points, normals, backend=backend, **kwargs)
    worst = angles_deg(from_module, from_cli).max()
    assert worst < kCliToleranceDeg, f"module and CLI differ by up to {worst} degrees"


def test_float32_and_strided_inputs_give_the_same_answer_in_their_dtype(backend):
    points, normals, _ = noisy_cube()
    # Values a float32 holds exactly, so all layouts below carry the same numbers.
    points = points.astype(np.float32).astype(np.float64)
    normals = normals.astype(np.float32).astype(np.float64)
    expected = pnf.improve_normals(points, normals, backend=backend)

    wide = np.zeros((len(points), 8))  # columns 1:4 and 4:7 of a wider array
    wide[:, 1:4], wide[:, 4:7] = points, normals
    layouts = {
        "float32": (points.astype(np.float32), normals.astype(np.float32)),
        "slices of a wider array": (wide[:, 1:4], wide[:, 4:7]),
        "Fortran order": (np.asfortranarray(points), np.asfortranarray(normals)),
        "float32 Fortran": (np.asfortranarray(points, np.float32), np.asfortranarray(normals, np.float32)),
        "list (copied)": (points.tolist(), normals.tolist()),
    }
    for name, (p, n) in layouts.items():
        assert pnf._pnf._view_info(p)["copied"] == (name == "list (copied)"), name
        out = pnf.improve_normals(p, n, backend=backend)
        # numpy users get the normals' dtype back: float32 in, the same normals rounded to float32 out.
        single = name.startswith("float32")
        assert out.dtype == (np.float32 if single else np.float64), name
        np.testing.assert_array_equal(out, expected.astype(out.dtype), err_msg=name)
    # The normals decide: float64 normals with float32 points give float64.
    assert pnf.improve_normals(points.astype(np.float32), normals, backend=backend).dtype == np.float64

    # Every other row: compared with a packed copy of the same rows.
    every_other = pnf.improve_normals(points[::2], normals[::2], backend=backend)
    packed = pnf.improve_normals(points[::2].copy(), normals[::2].copy(), backend=backend)
    np.testing.assert_array_equal(every_other, packed)


@pytest.mark.parametrize(
    "make",
    [
        lambda a: a,
        lambda a: a.astype(np.float32),
        lambda a: np.asfortranarray(a),
        lambda a: np.hstack([a, a])[:, 3:],
        lambda a: a[::-1],
        lambda a: a[::3],
    ],
    ids=["C float64", "C float32", "Fortran", "column slice", "reversed rows", "every third row"],
)
def test_float_inputs_are_read_in_place(make):
    array = make(np.arange(300.0).reshape(100, 3))
    info = pnf._pnf._view_info(array)
    assert not info["copied"]
    assert info["data"] == array.ctypes.data  # the address the library reads is the array's own
    assert (info["row_stride"], info["component_stride"]) == array.strides
    assert info["dtype"] == str(array.dtype)


@pytest.mark.parametrize(
    "make",
    [
        lambda a: a.astype(np.int64),
        lambda a: a.astype(np.float16),
        lambda a: a.astype(">f8"),
        lambda a: np.broadcast_to(a[:1], a.shape),
        lambda a: a.tolist(),
    ],
    ids=["int64", "float16", "big endian", "broadcast", "list"],
)
def test_other_inputs_are_copied_to_float64(make):
    source = np.arange(300.0).reshape(100, 3)
    array = make(source)
    info = pnf._pnf._view_info(array)
    assert info["copied"] and info["dtype"] == "float64"
    assert (info["row_stride"], info["component_stride"]) == (24, 8)


def test_no_copy_of_a_large_input():
    # numpy reports its allocations to tracemalloc: a copy of the inputs by the binding would
    # show as 2 x 48 MB; the output alone is 48 MB. (The library's own buffers are C++ and not
    # traced; the views it gets are checked by address above.)
    n = 2_000_000
    points = np.zeros((n, 3))
    points[:, 0] = np.arange(n) % 1000
    points[:, 1] = np.arange(n) // 1000
    normals = np.zeros((n, 3))
    normals[:, 2] = 1.0
    points.flags.writeable = False  # read-only arrays are fine: pnf only reads its inputs
    tracemalloc.start()
    try:
        # Neighbours within 2 sigma_f = 0.6 < spacing 1: each point is alone, so the run is quick.
        out = pnf.improve_normals(points, normals, iterations=1, units="absolute", sigma_f=0.3, backend="reference")
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert out.nbytes == 48_000_000
    assert peak < 1.2 * out.nbytes, f"peak traced memory {peak / 1e6:.1f} MB: an input was copied"


def test_out_receives_the_result_in_place(cube):
    points, normals, _ = cube
    expected = pnf.improve_normals(points, normals, backend="reference")
    out = np.zeros((len(points), 3), np.float32)
    assert pnf.improve_normals(points, normals, backend="reference", out=out) is out
    np.testing.assert_array_equal(out, expected.astype(np.float32))
    wide = np.zeros((len(points), 6))
    pnf.improve_normals(points, normals, backend="reference", out=wide[:, 3:])
    np.testing.assert_array_equal(wide[:, 3:], expected)
    assert (wide[:, :3] == 0).all()
    own = normals.copy()  # the normals themselves: read before written
    pnf.improve_normals(points, own, backend="reference", out=own)
    np.testing.assert_array_equal(own, expected)
    # One (N, 6) array of positions and normals, its normal columns as out: the columns share no
    # element with the positions', though their address ranges interleave.
    both = np.hstack([points, normals])
    pnf.improve_normals(both[:, :3], both[:, 3:], backend="reference", out=both[:, 3:])
    np.testing.assert_array_equal(both[:, 3:], expected)
    np.testing.assert_array_equal(both[:, :3], points)


def test_bad_out_raises_value_error(cube):
    points, normals, _ = cube
    for bad, match in [
        (np.zeros((len(points), 3), np.int32), "out must be"),
        (np.zeros((len(points) - 1, 3)), "out has"),
        (np.zeros((len(points), 3)).tolist(), "out must be"),
        (np.broadcast_to(np.zeros(3), (len(points), 3)), "out must be"),
        (points, "overlap points"),
    ]:
        with pytest.raises(ValueError, match=match):
            pnf.improve_normals(points, normals, backend="reference", out=bad)
    both = np.hstack([points, normals])  # out's first two columns are the points' last two
    with pytest.raises(ValueError, match="overlap points"):
        pnf.improve_normals(both[:, :3], both[:, 3:], backend="reference", out=both[:, 1:4])
    frozen = np.zeros((len(points), 3))
    frozen.flags.writeable = False
    with pytest.raises(ValueError, match="writable"):
        pnf.improve_normals(points, normals, backend="reference", out=frozen)


def test_progress_is_called_after_each_pass(cube):
    points, normals, _ = cube
    calls = []
    pnf.improve_normals(points, normals, iterations=3, backend="reference",
                        progress=lambda done, total, seconds: calls.append((done, total, seconds >= 0)))
    assert calls == [(1, 3, True), (2, 3, True), (3, 3, True)]


def test_a_progress_taking_stage_and_fraction_hears_every_stage_within_passes_too():
    # 60k points, about 10M pairs a pass: more than the first slice's 4M (filter_engine.cpp), so a
    # pass runs in several slices, each reported as "filtering" before the pass's end.
    points, normals, _ = noisy_cube(100)
    calls = []

    def progress(done, total, seconds, stage, fraction):
        calls.append((stage, done, total, fraction, seconds))

    pnf.improve_normals(points, normals, iterations=2, backend="reference", progress=progress)
    stages = [c[0] for c in calls]
    assert set(stages) == {"lists", "filtering", "pass"}, stages
    assert stages.index("lists") < stages.index("filtering") < stages.index("pass")
    assert [c[1:3] for c in calls if c[0] == "pass"] == [(1, 2), (2, 2)]
    assert all(0.0 <= c[3] <= 1.0 and c[4] >= 0 for c in calls)
    first_pass = [c for c in calls[:stages.index("pass")] if c[0] == "filtering"]
    assert len(first_pass) >= 2 and all(c[1] == 0 for c in first_pass)  # 0 passes done yet
    assert any(c[3] < 1.0 for c in first_pass)
    assert [c[3] for c in first_pass] == sorted(c[3] for c in first_pass)


def test_auto_reports_its_estimate_to_a_kwargs_progress(cube):
    points, normals, _ = cube
    stages = []
    pnf.improve_normals(points, normals, auto=True, backend="reference",
                        progress=lambda *args, **kw: stages.append(kw["stage"]))
    assert stages[0] == "estimate" and "pass" in stages


def test_false_from_a_report_within_a_pass_cancels_that_pass():
    points, normals, _ = noisy_cube(100)
    calls = []

    def progress(done, total, seconds, *, stage, fraction):
        calls.append(stage)
        return stage != "filtering"

    with pytest.raises(pnf.Cancelled):
        pnf.improve_normals(points, normals, iterations=2, backend="reference", progress=progress)
    assert calls[-1] == "filtering" and "pass" not in calls


def test_progress_returning_false_cancels(cube):
    points, normals, _ = cube
    with pytest.raises(pnf.Cancelled):
        pnf.improve_normals(points, normals, backend="reference", progress=lambda *_: False)
    assert issubclass(pnf.Cancelled, RuntimeError)
    # numpy's False too (a comparison's result), which once let the run go on.
    with pytest.raises(pnf.Cancelled):
        pnf.improve_normals(points, normals, backend="reference", progress=lambda *_: np.float64(1) > 2)
    # None (no return) and numpy's True go on.
    for keep_going in (lambda *_: None, lambda *_: np.float64(3) > 2):
        np.testing.assert_array_equal(
            pnf.improve_normals(points, normals, backend="reference", progress=keep_going),
            pnf.improve_normals(points, normals, backend="reference"))


def test_an_exception_in_progress_propagates(cube):
    points, normals, _ = cube

    def fail(done, total, seconds):
        raise ZeroDivisionError("from the callback")

    with pytest.raises(ZeroDivisionError, match="from the callback"):
        pnf.improve_normals(points, normals, backend="reference", progress=fail)


def test_ctrl_c_cancels_between_passes():
    # In a child process: SIGINT arrives from another thread while the main thread is in C++
    # with the GIL released; the next pass boundary raises KeyboardInterrupt.
    script = textwrap.dedent(
        """
        import os, signal, sys, threading, time
        sys.path.insert(0, sys.argv[1])
        import pnf
        from conftest import noisy_cube
        points, normals, _ = noisy_cube(24)
        threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
        start = time.monotonic()
        try:
            pnf.improve_normals(points, normals, iterations=100000, backend="reference", max_seconds=0)
        except KeyboardInterrupt:
            print("interrupted after %.1f s" % (time.monotonic() - start))
            sys.exit(0)
        sys.exit(3)
        """
    )
    from conftest import REPO

    done = subprocess.run([sys.executable, "-c", script, str(REPO / "python" / "tests")],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "interrupted" in done.stdout


def test_auto_is_never_worse_than_its_input(cube):
    # The noisy cube: auto=True filters it (choose_params's rule, passes judged) and gains.
    points, normals, truth = cube
    assert pnf.choose_params(points, normals).rule
    a = pnf.improve_normals(points, normals, auto=True, backend="reference")
    assert angles_deg(a, truth).mean() < 0.5 * angles_deg(normals, truth).mean()


def test_empty_cloud_gives_empty_normals():
    out = pnf.improve_normals(np.zeros((0, 3)), np.zeros((0, 3)), backend="reference")
    assert out.shape == (0, 3) and out.dtype == np.float64


def test_a_run_past_max_seconds_is_refused_with_the_numbers():
    from conftest import noisy_cube

    points, normals, _ = noisy_cube(24)
    with pytest.raises(ValueError, match=r"would take about .* times 100000 passes"):
        pnf.improve_normals(points, normals, iterations=100000, backend="reference", max_seconds=1)
    with pytest.raises(ValueError, match="max_seconds"):
        pnf.improve_normals(points, normals, backend="reference", max_seconds=-1)


def test_auto_judges_independent_normal_errors():
    from conftest import angles_deg, noisy_cube

    # Tilted true normals: errors independent of the positions, as a scanner's.
    points, normals, truth = noisy_cube(24)
    choice = pnf.choose_params(points, normals, backend="reference")
    assert "independent of the positions" in choice.rule
    a = pnf.improve_normals(points, normals, auto=True, backend="reference")
    before = np.sqrt(np.mean(np.minimum(angles_deg(normals, truth), 180 - angles_deg(normals, truth)) ** 2))
    after = np.sqrt(np.mean(np.minimum(angles_deg(a, truth), 180 - angles_deg(a, truth)) ** 2))
    assert after < 0.5 * before, (before, after, choice.rule)

"""The GIL is released during a solve, and Ctrl-C stops a long one."""

import os
import signal
import threading
import time

import pytest

import viscoslide as vs


def test_another_thread_runs_during_a_solve(rubber):
    surface = vs.Surface.self_affine(512, 0.01, 0.8, scales=64, rms_slope=0.02, rolloff_q0=5026.548, seed=1)
    counter = [0]
    stop = threading.Event()

    def count():
        # Sleeping releases the GIL between increments, so the counter
        # barely takes the CPU from the solve; it can only advance while
        # the solve does not hold the GIL.
        while not stop.is_set():
            counter[0] += 1
            time.sleep(0.001)

    thread = threading.Thread(target=count)
    thread.start()
    try:
        time.sleep(0.05)
        before = counter[0]
        t0 = time.perf_counter()
        result = vs.solve(surface, rubber, xi=1.17e-2, normal_load=0.3, backend="cpu")
        elapsed = time.perf_counter() - t0
        during = counter[0] - before
    finally:
        stop.set()
        thread.join()
    assert result.pressure.shape == (512, 512)
    # A thread starved of the GIL would not count at all; a free one counts
    # up to a thousand per second.
    assert during >= 20, f"the counter advanced by {during} during a {elapsed:.2f} s solve"


@pytest.mark.skipif(os.name != "posix", reason="SIGINT from a thread needs POSIX signals")
def test_ctrl_c_interrupts_a_long_solve_within_two_seconds(rubber, pad):
    surface = vs.Surface.self_affine(2048, 0.01, 0.8, scales=256, rms_slope=0.02, rolloff_q0=5026.548, seed=1)
    sent = []

    def interrupt():
        sent.append(time.perf_counter())
        os.kill(os.getpid(), signal.SIGINT)

    # Python turns SIGINT into KeyboardInterrupt only where the process
    # started with it at its default; a shell's background job (`cmd &`)
    # inherits it ignored. Install Python's handler for this test.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(0.5, interrupt)
    t0 = time.perf_counter()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            # One 2048^2 grid (no cascade) at a tolerance beyond reach:
            # seconds of work at the least, so the solve is running when
            # the signal comes.
            vs.solve(
                surface,
                rubber,
                xi=1.17e-2,
                normal_load=0.3,
                backend="cpu",
                formulation="periodic",
                cascade_levels=1,
                tolerance=1e-15,
                max_matvecs=5000,
            )
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)
    raised = time.perf_counter()
    assert sent, f"the solve ended after {raised - t0:.2f} s, before the signal"
    assert raised - sent[0] < 2.0, f"KeyboardInterrupt {raised - sent[0]:.2f} s after the signal"
    # The module is usable afterwards.
    assert vs.solve(pad, rubber, xi=1.17e-2, normal_load=0.3, backend="cpu").friction_coefficient > 0


def test_progress_callback_sees_every_iteration(pad, rubber):
    seen = []
    r = vs.solve(pad, rubber, xi=1.17e-2, normal_load=0.3, backend="cpu", progress=seen.append)
    assert seen, "no progress reported"
    assert set(seen[0]) == {"iteration", "matvecs", "residual", "contact_cells"}
    assert seen[-1]["residual"] == r.convergence["residual"]


def test_an_exception_in_the_callback_stops_the_solve(pad, rubber):
    def fail(info):
        raise RuntimeError("stop here")

    with pytest.raises(RuntimeError, match="stop here"):
        vs.solve(pad, rubber, xi=1.17e-2, normal_load=0.3, backend="cpu", progress=fail)


def test_progress_true_shows_a_tqdm_bar(pad, rubber, capsys):
    pytest.importorskip("tqdm")
    vs.solve(pad, rubber, xi=1.17e-2, normal_load=0.3, backend="cpu", progress=True)
    assert "active-set iterations" in capsys.readouterr().err


@pytest.mark.skipif(os.name != "posix", reason="SIGINT from a thread needs POSIX signals")
@pytest.mark.filterwarnings("ignore:the shortest roughness wavelength")
def test_ctrl_c_interrupts_the_heat_of_a_result(repo):
    """``Result.heat`` polls Ctrl-C between its volume source's depth
    layers: a signal a quarter into the computation raises
    ``KeyboardInterrupt`` within less than half of the whole computation's
    time (measured first, on the same machine), not at its end."""
    result = vs.solve_config(
        repo / "configs" / "paper_experiment.toml",
        set={"surface.generate.n": 512, "loading.temperature": 17.0, "analysis.enabled": False},
        backend="cpu",
    )
    t0 = time.perf_counter()
    result.heat(0.25, 1.16e-7, block_length=0.01)
    whole = time.perf_counter() - t0
    sent = []

    def interrupt():
        sent.append(time.perf_counter())
        os.kill(os.getpid(), signal.SIGINT)

    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(0.25 * whole, interrupt)
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            result.heat(0.25, 1.16e-7, block_length=0.01)
            # Finished before the signal: wait for it here.
            time.sleep(5.0)
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)
    raised = time.perf_counter()
    assert sent
    assert raised - sent[0] < 0.5 * whole, f"KeyboardInterrupt {raised - sent[0]:.2f} s after the signal; the whole heat takes {whole:.2f} s"
    # The result is usable afterwards.
    assert result.heat(0.25, 1.16e-7, block_length=0.01)["effective_rise_k"] > 0

"""Long runs are interruptible and visible: Ctrl-C raises KeyboardInterrupt at once (never a
panic), and ``progress=`` shows how far a run is."""

import os
import signal
import subprocess
import sys
import textwrap
import time

import pytest

import eamadm
from test_experiment import small_task1

# Started in a child process: prints "started" once the first run has finished (the call is
# under way), then waits in `eamadm.run`; on KeyboardInterrupt it prints the monotonic time it
# caught it at.
CHILD = textwrap.dedent(
    """
    import sys, time, traceback
    import eamadm

    def progress(done, total):
        if done == 1:
            print("started", flush=True)

    try:
        eamadm.run(eamadm.paper_config("task2"), threads=1, progress=progress)
    except KeyboardInterrupt:
        print("caught", time.monotonic(), flush=True)
        sys.exit(0)
    except BaseException:
        traceback.print_exc()
        sys.exit(3)
    print("finished without an interrupt", flush=True)
    sys.exit(4)
    """
)


@pytest.mark.skipif(sys.platform == "win32", reason="SIGINT")
def test_ctrl_c_raises_keyboard_interrupt_within_a_second():
    child = subprocess.Popen(
        [sys.executable, "-c", CHILD],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        assert child.stdout is not None
        line = child.stdout.readline()
        assert line.strip() == "started", line + child.stderr.read()
        # Well inside the run (the full Task II preset takes many seconds on one thread).
        time.sleep(0.3)
        sent = time.monotonic()
        child.send_signal(signal.SIGINT)
        out, err = child.communicate(timeout=60)
    finally:
        if child.poll() is None:
            child.kill()
    assert child.returncode == 0, out + err
    assert "PanicException" not in err and "panicked" not in err, err
    caught = float(out.split("caught", 1)[1].split()[0])
    assert caught - sent < 1.0, f"KeyboardInterrupt came {caught - sent:.2f} s after SIGINT"


def test_progress_callback_sees_every_run():
    calls = []
    eamadm.run(
        small_task1(episodes=2, seeds=2),
        methods=["softmax", "ea-madm"],
        progress=lambda done, total: calls.append((done, total)),
        dataframe=False,
    )
    assert calls == [(1, 4), (2, 4), (3, 4), (4, 4)]


def test_a_failing_progress_callback_stops_the_run():
    def fail(done, total):
        raise RuntimeError("stop here")

    with pytest.raises(RuntimeError, match="stop here"):
        eamadm.run(small_task1(episodes=2, seeds=2), progress=fail)


def test_progress_true_draws_a_bar(capsys):
    pytest.importorskip("tqdm")
    eamadm.run(small_task1(episodes=2, seeds=1), methods=["softmax"], progress=True)
    assert "1/1" in capsys.readouterr().err


def test_progress_true_without_tqdm_prints_a_line(capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "tqdm", None)
    eamadm.run(small_task1(episodes=2, seeds=2), methods=["softmax"], progress=True)
    err = capsys.readouterr().err
    assert "task1-small: 2/2 runs" in err and err.endswith("\n")


def test_progress_must_be_a_bool_or_a_callable():
    with pytest.raises(TypeError, match="^progress: "):
        eamadm.run(small_task1(episodes=2, seeds=1), progress="yes")

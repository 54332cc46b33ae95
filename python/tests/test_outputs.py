"""`Scenario.run(out=…)` and `Scenario.load`: every problem of the output folder is found
before the run and changes nothing, a failure to write after the run keeps the run's result,
and loading does not hold the GIL."""

import os
import pathlib
import subprocess
import sys
import textwrap

import pytest

import harmonav
from conftest import SCENARIOS

MIXED = SCENARIOS / "shapes" / "mixed.toml"


def tree(d):
    """Every entry below `d` with its bytes (files) or None (folders, links), sorted."""
    out = []
    for root, dirs, files in os.walk(d):
        for name in dirs + files:
            p = pathlib.Path(root) / name
            out.append((str(p), p.read_bytes() if p.is_file() and not p.is_symlink() else None))
    return sorted(out)


def test_an_empty_out_is_refused_and_the_current_folder_is_untouched(tmp_path, monkeypatch):
    # Before, out="" wrote into the current folder and deleted its speed.svg and energy.svg.
    monkeypatch.chdir(tmp_path)
    (tmp_path / "speed.svg").write_text("mine")
    (tmp_path / "energy.svg").write_text("mine too")
    before = tree(tmp_path)
    sc = harmonav.Scenario.load(MIXED)
    with pytest.raises(ValueError, match="empty"):
        sc.run(out="")
    assert tree(tmp_path) == before


def unwritable(tmp_path):
    """A folder where nothing can be created: read-only, or for root (who writes anywhere)
    /sys, which refuses new entries to everyone."""
    ro = tmp_path / "read-only"
    ro.mkdir()
    ro.chmod(0o555)
    try:
        (ro / "x").mkdir()
    except OSError:
        return ro
    (ro / "x").rmdir()
    return pathlib.Path("/sys")


def test_every_out_problem_is_found_before_the_run_and_changes_nothing(tmp_path):
    # Before, these were found only after the whole run, with the system's bare message (and
    # a folder named summary.json left a mixed set).
    sc = harmonav.Scenario.load(MIXED)
    (tmp_path / "a-file").write_text("keep")
    (tmp_path / "dangling").symlink_to(tmp_path / "nowhere")
    (tmp_path / "loop").symlink_to(tmp_path / "loop")
    taken = tmp_path / "taken"
    sc.run(out=taken)
    (taken / "summary.json").unlink()
    (taken / "summary.json").mkdir()
    ro = unwritable(tmp_path)
    long = tmp_path.joinpath(*[f"{i:0>200}" for i in range(20)])
    before = tree(tmp_path)
    cases = [
        (tmp_path / "a-file" / "out", "a-file is a file"),
        (tmp_path / "dangling", "is a symbolic link to .* which does not exist"),
        (tmp_path / "loop" / "out", "is a symbolic link that loops"),
        (ro / "out", "cannot create anything in"),
        (long, "PATH_MAX"),
        (taken, r"summary\.json: is a directory"),
    ]
    for out, words in cases:
        with pytest.raises(ValueError, match=f"^out: .*{words}.*nothing was run"):
            sc.run(out=out)
    assert tree(tmp_path) == before
    if ro != pathlib.Path("/sys"):
        ro.chmod(0o755)


# Runs in a child process: the file-size limit (and SIGXFSZ ignored, so that the write fails
# with EFBIG instead of killing the process) would otherwise apply to pytest too.
WRITE_FAILS = textwrap.dedent(
    """
    import resource, signal, sys
    import harmonav
    sc = harmonav.Scenario.load(sys.argv[1])
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (1024, resource.RLIM_INFINITY))
    try:
        sc.run(out=sys.argv[2])
    except OSError as e:
        assert e.summary is e.result.summary, "the same summary"
        assert len(e.result.t) > 10 and e.summary["reached"], e.summary
        print("OSError:", e)
    """
)


def test_the_run_is_kept_when_writing_the_outputs_fails(tmp_path):
    # Before, the error came without the run: its summary was lost.
    out = tmp_path / "out"
    harmonav.Scenario.load(MIXED).run(out=out)
    before = tree(tmp_path)
    child = subprocess.run(
        [sys.executable, "-c", WRITE_FAILS, str(MIXED), str(out)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert child.returncode == 0, child.stderr
    assert "OSError: out: the outputs were not written" in child.stdout, child.stdout
    assert "run.mcap" in child.stdout
    assert tree(tmp_path) == before, "the previous set is whole, no staging folder"


LOAD_FIFO = textwrap.dedent(
    """
    import sys
    import harmonav
    for load in (harmonav.Scenario.load, harmonav.FloorPlan.load):
        try:
            load(sys.argv[1])
        except ValueError as e:
            print(e)
    """
)


def test_loading_a_fifo_is_refused_without_blocking(tmp_path):
    # Before, the loader blocked in open() (first holding the GIL, then without it, waiting for
    # a writer); a FIFO, like a folder or a device, is now refused before it is opened
    # (hostile round 2026-12-06, D14). In a child, so that a regression hangs only the child.
    fifo = tmp_path / "scenario.toml"
    os.mkfifo(fifo)
    child = subprocess.run(
        [sys.executable, "-c", LOAD_FIFO, str(fifo)],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert child.returncode == 0, child.stderr
    lines = child.stdout.splitlines()
    assert len(lines) == 2, child.stdout
    assert all("scenario.toml" in ln and "not a regular file" in ln for ln in lines), lines

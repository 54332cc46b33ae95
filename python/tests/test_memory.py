"""Large requests raise MemoryError and the interpreter lives on (issue 23: `outline(2**40)` and
batch calls under a memory limit used to abort the process with SIGABRT).

Each case runs in a child interpreter whose address space is capped with RLIMIT_AS a little
above what it already uses, so that the allocations of the call under test cannot succeed. The
input arrays are made with `np.zeros` before the cap: their pages are never touched, so they
cost address space but no memory."""

import subprocess
import sys
import textwrap

import pytest

import harmonav

pytestmark = pytest.mark.skipif(
    sys.platform != "linux", reason="RLIMIT_AS and /proc/self/statm are Linux's"
)

MIB = 1 << 20

CHILD = """
import resource
import numpy as np
import harmonav

field = harmonav.Field(harmonav.circle([0, 0], 5.0), [harmonav.circle([1, 0], 0.5)], [3, 0])
shape = harmonav.star([0, 0], 1.0, [(3, 0.1, 0.0)])
{setup}
headroom = {headroom}
if headroom is not None:
    with open("/proc/self/statm") as f:
        used = int(f.read().split()[0]) * resource.getpagesize()
    resource.setrlimit(resource.RLIMIT_AS, (used + headroom, resource.RLIM_INFINITY))
try:
    {call}
except MemoryError as e:
    print("MemoryError:", e)
else:
    print("no error")
# The interpreter still works after the refusal, and small calls still succeed.
print("after:", float(shape.signed_distance([0.0, 0.0])) < 0.0)
"""


def run_capped(call, headroom, setup=""):
    """Runs `call` in a child whose address space is capped at its use plus `headroom` bytes
    (not capped for `None`); returns its stdout after checking that it exited normally (an
    abort would end this test run)."""
    script = CHILD.format(setup=textwrap.dedent(setup), headroom=headroom, call=call)
    child = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=300
    )
    assert child.returncode == 0, (child.returncode, child.stdout, child.stderr)
    assert "after: True" in child.stdout, child.stdout
    return child.stdout


def test_outline_of_2_to_the_40_points_raises_memory_error_naming_the_cap():
    # No memory limit needed: the cap refuses it before anything is allocated.
    out = run_capped("shape.outline(2**40)", headroom=None)
    assert "MemoryError: outline: n = 1099511627776" in out, out
    with pytest.raises(MemoryError, match=r"n = 1099511627776 .*cap of 16777216"):
        harmonav.circle([0, 0], 1.0).outline(2**40)
    with pytest.raises(MemoryError, match="cap"):
        harmonav.circle([0, 0], 1.0).outline(2**80)
    with pytest.raises(ValueError, match=r"n must be .*≥ 0, got -1"):
        harmonav.circle([0, 0], 1.0).outline(-1)
    assert harmonav.circle([0, 0], 1.0).outline(0).shape == (0, 2)


def test_outline_at_the_cap_under_a_memory_limit_raises_memory_error():
    # 2**24 points need a 256 MiB array: NumPy cannot make it within 64 MiB.
    out = run_capped("shape.outline(2**24)", headroom=64 * MIB)
    assert "MemoryError: outline" in out, out


@pytest.mark.parametrize(
    "call",
    ["field.eval(pts)", "field.free(pts)", "shape.signed_distance(pts)"],
)
def test_batches_under_a_memory_limit_raise_memory_error(call):
    # 2**23 points: the 128 MiB copy of the points cannot be made within 16 MiB.
    out = run_capped(call, headroom=16 * MIB, setup="pts = np.zeros((2**23, 2))")
    assert "MemoryError: points_xy" in out, out


def test_eval_whose_outputs_do_not_fit_raises_memory_error():
    # The copy of the points (128 MiB) fits; Θ (64 MiB) then does not fit in the 16 MiB left,
    # so this reaches the creation of the NumPy outputs (eval copies the points first).
    out = run_capped("field.eval(pts)", headroom=(128 + 16) * MIB, setup="pts = np.zeros((2**23, 2))")
    assert "MemoryError: theta" in out, out


def test_a_float32_batch_whose_cast_does_not_fit_raises_memory_error():
    out = run_capped(
        "field.eval(pts)", headroom=16 * MIB, setup="pts = np.zeros((2**23, 2), dtype=np.float32)"
    )
    assert "MemoryError: points_xy" in out, out

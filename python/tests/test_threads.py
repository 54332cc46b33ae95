"""Navigators shared between threads (hostile round 2026-12-06, D7): a lidar callback thread
runs `observe_scan` (which releases the GIL) beside a control loop. Calls from the second
thread wait for the scan instead of raising `RuntimeError: Already borrowed`."""

import copy
import math
import threading
import time

import numpy as np

import harmonav

SQUARE = [[0.0, 0.0], [8.0, 0.0], [8.0, 8.0], [0.0, 8.0]]


def hammer(nav, scan_args, calls, seconds=1.5):
    """Scans in a thread for `seconds` while this thread calls `calls(nav)` in a loop; returns
    the errors other than the navigator's own refusals (ValueError), and how many scans and
    calls ran."""
    errors, scans, done = [], [0], threading.Event()

    def lidar():
        rng = np.random.default_rng(0)
        end = time.monotonic() + seconds
        try:
            while time.monotonic() < end:
                position, ranges = scan_args(rng)
                step = 2 * math.pi / len(ranges)
                try:
                    nav.observe_scan(position, 0.0, ranges, -math.pi, step, 3.0)
                except ValueError:
                    pass  # a refused scan (not a star world): the navigator's own answer
                scans[0] += 1
        except Exception as e:  # noqa: BLE001  (recorded for the assertion below)
            errors.append(e)
        finally:
            done.set()

    thread = threading.Thread(target=lidar, daemon=True)
    thread.start()
    count = 0
    while not done.is_set():
        try:
            calls(nav)
        except ValueError:
            pass
        except Exception as e:  # noqa: BLE001
            errors.append(e)
        count += 1
    thread.join(timeout=60)
    assert not thread.is_alive(), "the scan thread did not finish (a deadlock?)"
    return errors, scans[0], count


def test_a_navigator_serialises_calls_from_two_threads():
    nav = harmonav.Navigator(harmonav.circle([0, 0], 10.0), goal=[8, 0], radius=0.1)

    def noisy(rng):
        return [-3.0, 0.0], rng.uniform(1.0, 3.0, 45)

    def calls(nav):
        nav.command([-3.0, 0.0])
        nav.theta([-3.0, 0.0])
        _ = nav.k, nav.obstacle_count, nav.mode, nav.perceived
        copy.copy(nav)

    errors, scans, count = hammer(nav, noisy, calls)
    assert errors == [], errors[:3]
    assert scans >= 1 and count >= 1


def test_a_floor_navigator_serialises_calls_from_two_threads():
    nav = harmonav.FloorNavigator(SQUARE, [7.0, 7.0], radius=0.1, max_element=0.2)

    def noisy(rng):
        return [1.0, 1.0], rng.uniform(1.0, 3.0, 45)

    def calls(nav):
        nav.command([1.0, 1.0])
        nav.theta([1.0, 1.0])
        _ = nav.k, nav.obstacles, nav.mode, nav.escapes
        copy.copy(nav)

    errors, scans, count = hammer(nav, noisy, calls)
    assert errors == [], errors[:3]
    assert scans >= 1 and count >= 1


def test_a_call_waits_for_a_scan_in_progress():
    """While one thread scans, a command from another returns after the scan, not with an
    error: it sees the navigator either before or after the scan, never during it."""
    nav = harmonav.Navigator(harmonav.circle([0, 0], 10.0), goal=[8, 0], radius=0.1)
    ranges = np.random.default_rng(0).uniform(1.0, 3.0, 45)
    started = threading.Event()
    result = {}

    def lidar():
        started.set()
        try:
            result["scan"] = nav.observe_scan([-3, 0], 0.0, ranges, -math.pi, 2 * math.pi / 45, 3.0)
        except ValueError as e:
            result["scan"] = e

    thread = threading.Thread(target=lidar)
    thread.start()
    started.wait()
    for _ in range(200):
        _ = nav.k  # a read must not raise while the scan runs
        try:
            nav.command([-3.0, 0.0])
        except ValueError:
            pass  # the scan may have perceived a shape over the robot: a refusal, not a race
    thread.join(timeout=120)
    assert not thread.is_alive()
    assert "scan" in result

"""register() releases the GIL: a Python thread keeps running during a registration, and
registrations in threads run side by side. Ctrl-C stops a registration.

A ticker thread records a timestamp every millisecond or so. Holding the GIL for the whole call,
register() would leave one gap in the ticks as long as the registration; released, the gaps stay
small. The bound (the longest gap under half the registration's time, the registration lasting
0.1 s at least) leaves the scheduler a wide margin either way."""
import threading
import time

import numpy as np
import pytest

import ppcr
from support import blob, rigid, rotation, transform


def test_a_python_thread_runs_during_a_registration():
    T = rigid(rotation([0.3, -0.2, 1.0], 12.0), [0.04, -0.03, 0.02])
    target = blob(6000, seed=1)
    source = transform(np.linalg.inv(T), blob(5000, seed=2))
    ticks = []
    done = threading.Event()

    def ticker():
        while not done.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    thread = threading.Thread(target=ticker)
    thread.start()
    try:
        while len(ticks) < 5:  # the ticker is running
            time.sleep(0.001)
        iterations = 60
        while True:
            start = time.perf_counter()
            r = ppcr.register(source, target, radius=0.1, criteria="fixed",
                              fixed_iterations=iterations, max_iterations=iterations)
            end = time.perf_counter()
            if end - start >= 0.1:
                break
            iterations *= 2  # a fast machine: a longer registration
    finally:
        done.set()
        thread.join()
    assert r.iterations == iterations
    inside = [start] + [t for t in ticks if start < t < end] + [end]
    longest_gap = max(b - a for a, b in zip(inside, inside[1:]))
    assert longest_gap < 0.5 * (end - start), (
        f"no tick for {longest_gap * 1e3:.0f} ms of a {(end - start) * 1e3:.0f} ms registration "
        f"({len(inside) - 2} ticks during it)")


def test_registrations_in_threads_give_the_sequential_answers():
    pairs = [(blob(3000, seed=2 * i + 10), blob(3000, seed=2 * i + 11)) for i in range(3)]
    sequential = [ppcr.register(s, t, radius=0.1).transformation for s, t in pairs]
    results = [None] * len(pairs)

    def run(i):
        results[i] = ppcr.register(*pairs[i], radius=0.1).transformation

    threads = [threading.Thread(target=run, args=(i,)) for i in range(len(pairs))]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert all(np.array_equal(a, b) for a, b in zip(results, sequential))


def test_ctrl_c_stops_a_registration():
    """A SIGINT arriving during a registration (interrupt_main simulates it) raises
    KeyboardInterrupt at the next iteration instead of after the whole registration."""
    import _thread
    source, target = blob(3000, seed=20), blob(3000, seed=21)
    timer = threading.Timer(0.05, _thread.interrupt_main)
    start = time.perf_counter()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            # 20000 iterations: several seconds, unless interrupted.
            ppcr.register(source, target, radius=0.1, criteria="fixed", fixed_iterations=20000,
                          max_iterations=20000)
    finally:
        timer.cancel()
    assert time.perf_counter() - start < 3.0

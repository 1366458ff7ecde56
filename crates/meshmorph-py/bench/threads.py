"""Two Python threads, each transferring 24 poses with `apply`, against one
thread doing the same alone: the GIL released while the work runs makes
the two finish in about the time of one (holding it would make it twice).
A timing, and so a benchmark, not a test: on a busy machine the ratio
rises (the test suite checks the GIL released without timing anything:
tests/test_hostile.py). Prints the fastest of 3 runs each and the ratio.

    python crates/meshmorph-py/bench/threads.py   (with meshmorph installed)
"""

import os
import sys
import threading
import timeit
from pathlib import Path

import numpy as np

import meshmorph

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from test_meshmorph import bent, sheet  # noqa: E402


def main():
    if (os.cpu_count() or 1) < 2:
        print("needs two cores")
        return 1
    vs, fs = sheet(90)
    vt, ft = sheet(110, 1.5)
    corner = lambda n: [0, n, n * (n + 1), (n + 1) ** 2 - 1]
    c = meshmorph.correspond(vs, fs, vt, ft, np.array(list(zip(corner(90), corner(110)))))
    t = meshmorph.Transfer(vs, fs, vt, ft, c)
    pose = bent(vs, 1.0)
    work = lambda: [t.apply(pose) for _ in range(24)]

    def two():
        threads = [threading.Thread(target=work) for _ in range(2)]
        for th in threads:
            th.start()
        for th in threads:
            th.join()

    work()
    one_time, two_time = (min(timeit.repeat(f, number=1, repeat=3)) for f in (work, two))
    print(f"one thread: {one_time * 1e3:.0f} ms; two threads, twice the work: {two_time * 1e3:.0f} ms; ratio {two_time / one_time:.2f} (1 is ideal, 2 is the GIL held)")
    return 0


if __name__ == "__main__":
    sys.exit(main())

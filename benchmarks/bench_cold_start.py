"""The first result on a fresh machine: each first use in a fresh kernel cache and a fresh process, beside its
warm time (issue "Start in seconds").

``python benchmarks/bench_cold_start.py [--only run,reproduce,python] [--json FILE]``

For each of the three first results a new user meets,

- ``run``: ``uvms run paper_case3_controlled -o DIR`` (the CLI),
- ``reproduce``: ``uvms reproduce paper -o DIR`` (the CLI, every figure, report and replay),
- ``python``: ``import uvms; uvms.simulate(uvms.load_model("paper"), duration=10, step=1e-3,
  joint_torques=paper_torques())`` in a fresh interpreter,

it runs the command twice in a new process each time, with ``NUMBA_CACHE_DIR`` pointing at a folder made empty
for that command: the first run is **cold** (a fresh cache folder, as on a fresh machine: it gets the kernels
that ``pip install`` compiled, ``uvms._cache.seed``), the second **warm** (the cache the first one left). With
``--from-nothing`` the cold run gets no prebuilt kernels either (``UVMS_NO_PREBUILT=1``): every kernel it needs
compiles, as before kernels were compiled at install. It prints the wall times, the cold-minus-warm penalty (the
issue's target: at most 20 s), and the longest silence of the cold run (the longest time between two lines the
process printed, stdout and stderr merged; the target: at most 10 s), so a compile that says nothing shows up.

Wall times include the interpreter's start and imports, as a user sees them. The VM's speed moves by +-20 % from
minute to minute; the load average is printed with the table.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import selectors
import subprocess
import sys
import tempfile
import time
from pathlib import Path

PYTHON_FIRST_SIMULATE = (
    "import uvms\n"
    "from uvms.sim.inputs import paper_torques\n"
    "model = uvms.load_model('paper')\n"
    "result = uvms.simulate(model, duration=10.0, step=1e-3, joint_torques=paper_torques())\n"
    "print('simulated', len(result.time), 'rows')\n"
)


def commands(out: Path) -> dict[str, list[str]]:
    """The three first results (module docstring) as argument lists for a fresh process."""
    uvms = [sys.executable, "-m", "uvms"]
    return {"run": [*uvms, "run", "paper_case3_controlled", "-o", str(out / "run")],
            "reproduce": [*uvms, "reproduce", "paper", "-o", str(out / "reproduce")],
            "python": [sys.executable, "-c", PYTHON_FIRST_SIMULATE]}


def timed(argv: list[str], env: dict[str, str]) -> tuple[float, float, int, str]:
    """``(wall time [s], longest silence [s], exit code, last lines)`` of one process; its output is read line by
    line as it comes (stdout and stderr merged) to time the gaps between lines."""
    start = time.perf_counter()
    process = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, env=env, bufsize=0)
    selector = selectors.DefaultSelector()
    selector.register(process.stdout, selectors.EVENT_READ)
    last, longest, tail = start, 0.0, b""
    while True:
        if not selector.select(timeout=1.0):
            if process.poll() is not None:
                break
            continue
        chunk = os.read(process.stdout.fileno(), 65536)
        if not chunk:
            break
        now = time.perf_counter()
        # a progress bar redraws with carriage returns: each redraw counts as a sign of life
        if b"\n" in chunk or b"\r" in chunk:
            longest, last = max(longest, now - last), now
        tail = (tail + chunk)[-2000:]
    code = process.wait()
    end = time.perf_counter()
    longest = max(longest, end - last)
    return end - start, longest, code, tail.decode("utf-8", "replace").strip().splitlines()[-3:]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", default="run,reproduce,python", help="comma-separated: run, reproduce, python")
    parser.add_argument("--json", type=Path, help="also write the figures to this JSON file")
    parser.add_argument("--from-nothing", action="store_true",
                        help="the cold run gets no prebuilt kernels (UVMS_NO_PREBUILT=1): a compile from nothing")
    args = parser.parse_args()
    rows = {}
    with tempfile.TemporaryDirectory(prefix="uvms-cold-") as tmp:
        tmp = Path(tmp)
        for name, argv in commands(tmp).items():
            if name not in args.only.split(","):
                continue
            cache = tmp / f"cache-{name}"
            cache.mkdir()
            env = {**os.environ, "NUMBA_CACHE_DIR": str(cache), "PYTHONUNBUFFERED": "1"}
            cold_env = {**env, "UVMS_NO_PREBUILT": "1"} if args.from_nothing else env
            cold, silence, code_cold, tail_cold = timed(argv, cold_env)
            warm, _, code_warm, tail_warm = timed(argv, env)
            rows[name] = {"cold_s": cold, "warm_s": warm, "penalty_s": cold - warm,
                          "longest_silence_cold_s": silence, "exit_codes": [code_cold, code_warm]}
            print(f"{name:10s} cold {cold:7.1f} s  warm {warm:6.1f} s  penalty {cold - warm:7.1f} s  "
                  f"longest silence (cold) {silence:6.1f} s  exit {code_cold}/{code_warm}", flush=True)
            if code_cold or code_warm:
                print("  last lines:", *(tail_cold if code_cold else tail_warm), sep="\n    ")
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"\n{platform.processor() or platform.machine()}, {os.cpu_count()} cores, load {load:.1f}; "
          "targets: penalty <= 20 s, longest silence <= 10 s")
    if args.json:
        args.json.write_text(json.dumps({"rows": rows, "load": load}, indent=2))


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Independent check of can/gvs.dbc with canmatrix (Debian: python3-canmatrix).

1. The DBC loads without any warning or error from canmatrix.
2. Every message and signal canmatrix sees is decoded from the frames the
   C++ codec encodes (gvs_can_examples --json) to the physical values the
   codec was given, within half a step; every DBC signal is covered.

Usage: check_dbc_canmatrix.py GVS_DBC GVS_CAN_EXAMPLES_BINARY
Installs nothing: fails with a clear message if canmatrix is missing.
"""
import contextlib
import io
import json
import logging
import subprocess
import sys


class Collect(logging.Handler):
    def __init__(self):
        super().__init__(level=logging.WARNING)
        self.records = []

    def emit(self, record):
        self.records.append(record)


def main():
    if len(sys.argv) != 3:
        print(__doc__)
        return 2
    dbc_path, examples_bin = sys.argv[1], sys.argv[2]
    try:
        import canmatrix.formats  # noqa: PLC0415
    except ImportError as e:
        print(f"FAIL: canmatrix is not importable ({e}); install Debian's python3-canmatrix "
              "and run this with /usr/bin/python3")
        return 1

    collector = Collect()
    logging.getLogger().addHandler(collector)
    logging.getLogger().setLevel(logging.WARNING)
    printed = io.StringIO()  # canmatrix prints parse errors instead of logging them
    with contextlib.redirect_stdout(printed), contextlib.redirect_stderr(printed):
        dbs = canmatrix.formats.loadp(dbc_path)
    problems = [f"{r.name}: {r.getMessage()}" for r in collector.records]
    problems += [line for line in printed.getvalue().splitlines() if line.strip()]
    if problems:
        print("FAIL: canmatrix warned while loading", dbc_path)
        for p in problems:
            print("  ", p)
        return 1
    db = dbs[""]
    frames = {f.arbitration_id.id: f for f in db.frames}
    with open(dbc_path, encoding="ascii") as f:
        dbc_messages = sum(1 for line in f if line.startswith("BO_ "))
    if dbc_messages != len(frames):
        print(f"FAIL: the DBC has {dbc_messages} BO_ lines but canmatrix loaded {len(frames)} messages")
        return 1
    print(f"canmatrix loaded {dbc_path}: {len(frames)} messages, no warnings")

    out = subprocess.run([examples_bin, "--json"], check=True, capture_output=True, text=True).stdout
    failures = 0
    covered = set()
    cases = [json.loads(line) for line in out.splitlines() if line.strip()]
    for case in cases:
        frame = frames.get(case["id"])
        if frame is None or frame.name != case["message"]:
            print(f"FAIL: ID {case['id']:#x} is {frame.name if frame else 'missing'} in the DBC, codec says {case['message']}")
            failures += 1
            continue
        data = bytes.fromhex(case["data"])
        decoded = frame.decode(data)
        names = {s.name for s in frame.signals}
        if names != set(case["expect"]):
            print(f"FAIL: {frame.name}: DBC signals {sorted(names ^ set(case['expect']))} differ from the codec's")
            failures += 1
        for name, expected in case["expect"].items():
            sig = frame.signal_by_name(name)
            if sig is None:
                continue
            value = float(decoded[name].raw_value) * float(sig.factor) + float(sig.offset)
            tolerance = float(sig.factor) / 2 + 1e-9
            covered.add((frame.name, name))
            if abs(value - expected) > tolerance:
                print(f"FAIL: {frame.name}.{name}: canmatrix decodes {value}, codec encoded {expected} "
                      f"(frame {case['data']})")
                failures += 1
    all_signals = {(f.name, s.name) for f in db.frames for s in f.signals}
    missing = all_signals - covered
    if missing:
        print("FAIL: DBC signals never checked:", sorted(missing))
        failures += 1
    print(f"{len(cases)} frames, {len(covered)} signals cross-checked, {failures} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

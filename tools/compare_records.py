#!/usr/bin/env python3
"""Compare two `opengrasp` results files, ignoring what legitimately differs between runs.

    python3 tools/compare_records.py BASE.json AFTER.json [--max 40]

Dropped before comparing: the `provenance` block (host, dates, versions, wall time) and every
timing field (keys ending in `_time`, `_seconds` or `_per_second`, with their summaries'
statistics). Everything else -- counts, verdicts, lengths, epsilons,
paths, parameters -- must be equal to the bit. Prints each difference with its JSON path and
exits 0 when the records are identical, 1 when they differ, 2 on unreadable input.
"""
import json
import sys


def is_timing(key):
    return key.endswith(("_time", "_seconds", "_per_second"))


def diff(a, b, path, out):
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if is_timing(k) or (path == "" and k == "provenance"):
                continue
            if k not in a or k not in b:
                out.append(f"{path}/{k}: only in {'after' if k not in a else 'base'}")
                continue
            diff(a[k], b[k], f"{path}/{k}", out)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            out.append(f"{path}: length {len(a)} vs {len(b)}")
        for i, (x, y) in enumerate(zip(a, b)):
            diff(x, y, f"{path}[{i}]", out)
    elif a != b:
        out.append(f"{path}: {json.dumps(a)[:120]} vs {json.dumps(b)[:120]}")


def main(argv):
    args = [a for a in argv[1:] if not a.startswith("--")]
    most = 40
    if "--max" in argv:
        most = int(argv[argv.index("--max") + 1])
        args = [a for a in args if a != str(most)]
    if len(args) != 2:
        print(__doc__.strip().splitlines()[2].strip(), file=sys.stderr)
        return 2
    try:
        base, after = (json.load(open(p)) for p in args)
    except (OSError, ValueError) as e:
        print(f"cannot read: {e}", file=sys.stderr)
        return 2
    out = []
    diff(base, after, "", out)
    for line in out[:most]:
        print(line)
    if len(out) > most:
        print(f"... and {len(out) - most} more")
    print(f"{len(out)} differences")
    return 1 if out else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

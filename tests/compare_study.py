#!/usr/bin/env python3
"""Two study report folders are the same study: results.json equal but for the timing figures
(and the fields that say where and in which job a row was timed), and every image file that
results.json names byte-identical. Usage: compare_study.py ONE OTHER"""
import json
import os
import sys

TIMING = {"ms", "run_ms", "fragments_per_second", "total_seconds", "threads", "jobs", "nodes", "node", "job"}


def without_timing(value):
    if isinstance(value, dict):
        return {k: without_timing(v) for k, v in value.items() if k not in TIMING}
    if isinstance(value, list):
        return [without_timing(v) for v in value]
    return value


def main(one, other):
    a = json.load(open(os.path.join(one, "results.json")))
    b = json.load(open(os.path.join(other, "results.json")))
    if without_timing(a) != without_timing(b):
        print(f"{one} and {other}: results.json differ beyond the timings")
        return 1
    images = 0
    for scene in a["scenes"]:
        if not scene["rows"]:
            print(f"{one}: scene {scene['name']} has no rows")
            return 1
        for row in scene["rows"]:
            for name in (row["image"], row["heatmap"]):
                with open(os.path.join(one, name), "rb") as x, open(os.path.join(other, name), "rb") as y:
                    if x.read() != y.read():
                        print(f"{name} differs between {one} and {other}")
                        return 1
                images += 1
    rows = sum(len(s["rows"]) for s in a["scenes"])
    print(f"same study: {len(a['scenes'])} scenes, {rows} rows, {images} images byte-identical, error figures equal")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))

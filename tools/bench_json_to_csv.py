#!/usr/bin/env python3
"""Google Benchmark JSON -> CSV (name, aggregate, real time, unit, and every user counter)."""
import csv
import json
import sys

data = json.load(open(sys.argv[1], encoding="utf-8"))
rows = data.get("benchmarks", [])
counters = sorted({k for r in rows for k, v in r.items()
                   if isinstance(v, (int, float)) and k not in (
                       "real_time", "cpu_time", "iterations", "repetitions", "repetition_index",
                       "threads", "family_index", "per_family_instance_index")})
w = csv.writer(sys.stdout)
w.writerow(["name", "label", "aggregate", "real_time", "time_unit"] + counters)
for r in rows:
    w.writerow([r.get("run_name", r["name"]), r.get("label", ""), r.get("aggregate_name", ""), r.get("real_time"),
                r.get("time_unit")] + [r.get(c, "") for c in counters])

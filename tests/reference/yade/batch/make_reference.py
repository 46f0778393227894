#!/usr/bin/env python3
"""Runs real YADE's yade-batch on both tables and collects what each job saw into yade_batch.json.

    cd tests/reference/yade/batch && python3 make_reference.py
"""
import glob
import json
import os
import subprocess

result = {}
for table in ("params.table", "params_nodesc.table"):
    for f in glob.glob("job-*.json") + glob.glob("*.log"):
        os.remove(f)
    run = subprocess.run(["yade-batch", "-j", "1", table, "sim.py"], capture_output=True, text=True, timeout=600)
    jobs = {}
    for f in sorted(glob.glob("job-*.json")):
        with open(f) as fh:
            jobs[f[4:-5]] = json.load(fh)
        os.remove(f)
    logs = sorted(glob.glob("*.log"))
    for f in logs:
        os.remove(f)
    result[table] = {"returncode": run.returncode, "jobs": jobs, "logs": logs}
with open("yade_batch.json", "w") as fh:
    json.dump(result, fh, indent=1, sort_keys=True)

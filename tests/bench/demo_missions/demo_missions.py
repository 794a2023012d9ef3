#!/usr/bin/env python3
"""Do the check poles' stated σ hold over many draws of one scenario?

Simulates N missions of a scenario (default: the demo's, config/examples/demo_scenario.json) with
seeds seed0 .. seed0+N-1 (`rangecal simulate`), runs each (`rangecal run`, compare methods left out
to save time) and compares every check pole's intersection (out/intersection.csv) with its true
position (truth.json): the rms of |ΔR| against the rms of the stated sigma_m, and the error split
into each mission's common shift (the mean over its poles: the datum) and the scatter about it.

  python3 tests/bench/demo_missions/demo_missions.py --rangecal build/rangecal --out /tmp/dm \
      [--missions 16] [--seed0 5000] [--scenario FILE] [--free f,k1,pose] [--stated-defaults]

--free replaces the scenario's mission_calibrate.free; --stated-defaults removes the survey and pick
σ the simulator states in mission.json (the run then states the config defaults, 5 mm and 0.5 px).
Standard library only.
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rangecal", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--scenario", default=os.path.join(os.path.dirname(__file__), "..", "..", "..",
                                                       "config", "examples", "demo_scenario.json"))
    ap.add_argument("--missions", type=int, default=16)
    ap.add_argument("--seed0", type=int, default=5000)
    ap.add_argument("--free", default="")
    ap.add_argument("--stated-defaults", action="store_true")
    a = ap.parse_args()
    base = json.load(open(a.scenario))
    errors, sigmas, shifts, scatter = [], [], [], []
    for k in range(a.missions):
        d = os.path.join(a.out, "m%03d" % k)
        os.makedirs(d, exist_ok=True)
        sc = dict(base)
        sc["seed"] = a.seed0 + k
        mc = dict(base.get("mission_calibrate", {}))
        mc.pop("compare", None)
        if a.free:
            mc["free"] = a.free.split(",")
        sc["mission_calibrate"] = mc
        json.dump(sc, open(os.path.join(d, "scenario.json"), "w"))
        subprocess.run([a.rangecal, "simulate", os.path.join(d, "scenario.json"), "--out",
                        os.path.join(d, "mission")], check=True, capture_output=True)
        mission = os.path.join(d, "mission", "mission.json")
        if a.stated_defaults:
            m = json.load(open(mission))
            m.pop("intersect", None)
            m["calibrate"].pop("control_sigma_m", None)
            for c in m["cameras"]:
                c.pop("pixel_sigma_px", None)
            json.dump(m, open(mission, "w"), indent=1)
        r = subprocess.run([a.rangecal, "run", mission], capture_output=True, text=True)
        if r.returncode != 0:
            print("mission %d: rangecal run exit %d\n%s" % (k, r.returncode, r.stderr[-2000:]), file=sys.stderr)
            continue
        truth = json.load(open(os.path.join(d, "mission", "truth.json")))
        true_enu = {p["id"]: p["true_enu_m"] for p in truth["poles"]}
        es = []
        for row in csv.DictReader(open(os.path.join(d, "mission", "out", "intersection.csv"))):
            t = true_enu[row["id"]]
            es.append([float(row["E"]) - t[0], float(row["N"]) - t[1], float(row["U"]) - t[2]])
            sigmas.append(float(row["sigma_m"]))
        mean = [sum(e[i] for e in es) / len(es) for i in range(3)]
        shifts.append(mean)
        for e in es:
            errors.append(sum(x * x for x in e))
            scatter.append(sum((e[i] - mean[i]) ** 2 for i in range(3)))
        print("mission %d: %d check poles" % (k, len(es)), flush=True)
    rms = lambda v: math.sqrt(sum(v) / len(v))
    err, sig = rms(errors), rms([s * s for s in sigmas])
    print("%d missions, %d check-pole intersections" % (len(shifts), len(errors)))
    print("error rms %.2f cm, stated sigma rms %.2f cm, error / stated %.2f" % (100 * err, 100 * sig, err / sig))
    print("common shift rms E N U %.2f %.2f %.2f cm; scatter about it %.2f cm" %
          (tuple(100 * math.sqrt(sum(s[i] ** 2 for s in shifts) / len(shifts)) for i in range(3)) +
           (100 * rms(scatter),)))


if __name__ == "__main__":
    main()

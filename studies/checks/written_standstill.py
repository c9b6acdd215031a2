#!/usr/bin/env python3
"""Written strapdown drives diagnosed with their tolerances stated off at random.

Twelve drives from `navkf simulate --model strapdown` (10 Hz, seeds and unit classes drawn),
each with `zupt_m_s` replaced by a draw log-uniform over 1e-4 to 1e-1 m/s (the car stands
exactly still: anything above ~1e-4 is over-stated) and `nhc_m_s` scaled by a factor
log-uniform over 0.3 to 3, then `navkf diagnose`d. One line a drive: the verdict, the named
effects, and the fitted constraint, standstill, accelerometer and gyro levels (docs/model.md,
"Diagnosing a strapdown unit", quotes the result).

    python3 studies/checks/written_standstill.py [NAVKF] [WORKDIR]

NAVKF defaults to ./target/release/navkf; WORKDIR (scratch, made if missing) to
/tmp/navkf-written-standstill. Standard library only.
"""
import json
import os
import random
import re
import subprocess
import sys

navkf = sys.argv[1] if len(sys.argv) > 1 else "./target/release/navkf"
navkf = os.path.abspath(navkf)
work = sys.argv[2] if len(sys.argv) > 2 else "/tmp/navkf-written-standstill"
os.makedirs(work, exist_ok=True)
rng = random.Random(20261201)
for k in range(12):
    seed = rng.randrange(1000, 9999)
    unit = rng.choice(["mems", "mems", "tactical"])
    zupt = 10 ** rng.uniform(-4, -1)
    nhc_factor = 10 ** rng.uniform(-0.5, 0.5)
    data = os.path.join(work, f"d{k}")
    out = os.path.join(work, f"r{k}")
    subprocess.run(
        [navkf, "simulate", "--model", "strapdown", "--unit", unit, "--imu-rate", "10",
         "--seed", str(seed), "--out", data],
        capture_output=True, check=True)
    path = os.path.join(data, "dataset.toml")
    text = open(path).read()
    nhc = float(re.search(r"^nhc_m_s = ([0-9.e+-]+)", text, re.M).group(1))
    text = re.sub(r"^zupt_m_s = .*$", f"zupt_m_s = {zupt:.3e}", text, flags=re.M)
    text = re.sub(r"^nhc_m_s = .*$", f"nhc_m_s = {nhc * nhc_factor:.4e}", text, flags=re.M)
    open(path, "w").write(text)
    subprocess.run([navkf, "diagnose", data, "--out", out], capture_output=True, check=True)
    d = json.load(open(os.path.join(out, "diagnosis.json")))
    fits = {s["source"]: f"{s['verdict']} {s['sigma_ratio']:.3g}" for s in d["noise"]["sources"]}
    print(f"{k:2} seed {seed} {unit:8} zupt {zupt:.1e} nhc x{nhc_factor:.2f}: {d['verdict']}, "
          f"named {d['effects']}; constraint {fits.get('constraint')}, standstill "
          f"{fits.get('standstill')}, accelerometer {fits.get('accelerometer')}, gyro "
          f"{fits.get('gyro')}", flush=True)

#!/usr/bin/env python3
"""rangecal's default run on the ETH drone-tracking flights, held out as eth_drone_tracking.py's baselines.

Run eth_drone_tracking.py first (its --out holds the exports, results.json and alignment.json). For
each dataset and split, this writes a mission whose cameras are the exports' tracks cut to the
calibration blocks (the same blocks, decided with the same alignment, as the baselines), with
`"clock": "estimate"` (rangecal finds each camera's offset and rate itself), runs rangecal's gnss,
align, detect and calibrate stages with the default method and model, reads each camera's
camera_opencv.yml and the clock rangecal found (run.json), and triangulates the held-out RTK epochs
exactly as the baselines do (labels interpolated to the fix instant, eth_drone_tracking.triangulate).
The predicted σ of each held-out point is the intersect stage's (calibration covariance + the
labels' σ): the held-out epochs are written as check poles and their labels as pole picks, with the
pick σ the mean of the image σ the network estimated for the cameras.

Usage: python3 tests/bench/real_flights/eth_rangecal.py --eth-out /tmp/eth --rangecal build/rangecal --out /tmp/eth_rc
Data stays outside the repository (CC BY-NC-SA 4.0): see README.md here.
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import eth_drone_tracking as eth  # noqa: E402  (re-execs under /usr/bin/python3 if numpy is missing)
import numpy as np  # noqa: E402


# A stretch of dataset 2 where the RTK itself is off: from 273.3 s to 282.1 s after its first fix
# (12:04:33.3-12:04:42.1 in the export) its position steps by about (+0.09, -0.11, +0.26) m and back
# (a fix jump), while every camera keeps agreeing with every other (views within 0.1-0.7 px). Both
# splits' calibrations -- independent, from complementary blocks -- see the same step, and rangecal's
# network rejects these fixes as PPK outliers where they fall in its calibration blocks. Figures are
# given with and without it (for the baselines too: their hold-out errors there are the same step).
RTK_STEP_S = {"dataset2": (273.3, 282.1)}


def outside_rtk_step(name, t_s):
    lo, hi = RTK_STEP_S.get(name, (np.inf, -np.inf))
    return ~((np.asarray(t_s) >= lo) & (np.asarray(t_s) <= hi))


def read_track_csv(path):
    rows = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return rows[:, 0].astype(int), rows[:, 1:3]


def opencv_camera(path):
    """K, dist, rvec, tvec from rangecal's camera_opencv.yml (OpenCV FileStorage)."""
    import cv2
    fs = cv2.FileStorage(path, cv2.FILE_STORAGE_READ)
    K, d = fs.getNode("camera_matrix").mat(), fs.getNode("distortion_coefficients").mat().ravel()
    rv, tv = fs.getNode("rvec").mat().ravel(), fs.getNode("tvec").mat().ravel()
    fs.release()
    return {"model": "B", "rx": rv[0], "ry": rv[1], "rz": rv[2], "tx": tv[0], "ty": tv[1], "tz": tv[2]}, {"K": K, "dist": d}


def label_at_rs(cam, p, pub, t):
    """eth_drone_tracking.label_at at the instant the label's row was exposed: a rolling shutter
    reads row v at frame time + tau (v/(H-1) - 1/2), so the frame position is found again at
    t - that delay, with v from the first interpolation (two passes: v barely moves in tau)."""
    uv, ok = eth.label_at(cam, p, pub["fps"], t)
    tau = p.get("tau", 0.0)
    if tau == 0.0:
        return uv, ok
    for _ in range(2):
        uv2, ok2 = eth.label_at(cam, p, pub["fps"], t - tau * (uv[:, 1] / (pub["height"] - 1) - 0.5))
        uv = np.where(ok2[:, None], uv2, uv)
        ok = ok & ok2
    return uv, ok


def triangulate_epochs_rs(ds, models, epochs):
    """eth_drone_tracking.triangulate_epochs with each label at its row's instant (label_at_rs)."""
    track = ds["track"]
    labels = [label_at_rs(cam, p, pub, track.t[epochs]) for cam, (p, pub) in zip(ds["cams"], models)]
    rows = []
    for j, e in enumerate(epochs):
        obs = [(lab[0][j], p, pub) for lab, (p, pub) in zip(labels, models) if lab[1][j]]
        if len(obs) < 2:
            continue
        X, rms = eth.triangulate(obs)
        rows.append((e, X, track.p[e], len(obs), rms, 0.0, "+".join(str(k) for k, lab in enumerate(labels) if lab[1][j])))
    return rows


def run(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode not in (0,):
        print(r.stdout[-3000:], r.stderr[-3000:])
        raise SystemExit(f"{' '.join(cmd)} exited {r.returncode}")
    return r.stdout


def score_trajectory(path, hold_set, track):
    """Each held-out instant of a trajectory.csv against the RTK fix there: errors, z, σ parts, times, extrapolated."""
    with open(path) as fh:
        tr = list(csv.DictReader(fh))
    t_err, t_z, t_parts, t_t, t_x = [], [], [], [], []
    for row in tr:
        hh, mm, ss = row["utc"].split("T")[1].rstrip("Z").split(":")
        k = int(round(((int(hh) - 12) * 3600 + int(mm) * 60 + float(ss)) / eth.RTK_DT))
        if k not in hold_set:
            continue
        e = np.array([float(row["E"]), float(row["N"]), float(row["U"])]) - track.p[k]
        t_err.append(e)
        t_z.append(np.linalg.norm(e) / float(row["sigma_m"]))
        t_parts.append([float(row[c]) for c in ("sigma_labels_m", "sigma_timing_m", "sigma_calibration_m")])
        t_t.append(track.t[k])
        t_x.append(row["extrapolated"] != "")
    return t_err, t_z, t_parts, t_t, t_x


def utc_text(t):
    """Seconds after 12:00 UTC of the dataset's day as the ISO 8601 the timestamps files use."""
    ns = int(round(t * 1e9)) + 12 * 3600 * 10**9
    s, frac = divmod(ns, 10**9)
    h, rest = divmod(s, 3600)
    m, sec = divmod(rest, 60)
    return f"2020-01-01T{h:02d}:{m:02d}:{sec:02d}.{frac:09d}Z"


def imported_mission(cfg, d, ds, eth_out, name, form):
    """The trajectory of `cfg`'s cameras as imported cameras: `form` "opencv_yml" (rangecal's own exports,
    calibration.json's marginal σ stated) or "rangecal_json" (each calibration.json, its covariance whole)."""
    runj = json.load(open(os.path.join(d, "out", "run.json")))
    native = runj["stages"]["trajectory"]["counts"]["cameras"]
    icfg = {k: v for k, v in cfg.items() if k not in ("cameras", "poles", "intersect")}
    icfg["cameras"] = []
    icfg["output_dir"] = os.path.join(d, "out_imported")
    imported = []
    for cam, cc in zip(ds["cams"], cfg["cameras"]):
        cid = cam["name"]
        cal = json.load(open(os.path.join(d, "out", cid, "calibration.json")))
        sg = cal["sigma"]
        pitch_mm = cc["sensor"]["pixel_size_um"][1] * 1e-3

        def rms(key):  # the stated σ of a group: the rms of its axes' marginal σ; none estimated is no statement
            v = sg[key]
            if v is None or (isinstance(v, list) and any(x is None for x in v)):
                raise SystemExit(f"{cid}: calibration.json states no σ for {key}: nothing to import it with")
            return float(np.sqrt(np.mean(np.square(v))))
        ck = runj["stages"]["align"]["counts"][cid]["clock"]
        n0 = ck["nominal_start_utc"]
        hh, mm, ss = n0.split("T")[1].rstrip("Z").split(":")
        n0_s = (int(hh) - 12) * 3600 + int(mm) * 60 + float(ss)
        src = os.path.join(eth_out, name, cid, "timestamps.csv")
        dst = os.path.join(d, cid, "target_utc.csv")
        with open(src) as fi, open(dst, "w") as fo:
            fo.write("frame,utc\n")
            for row in csv.DictReader(fi):
                hh, mm, ss = row["utc"].split("T")[1].rstrip("Z").split(":")
                t = (int(hh) - 12) * 3600 + int(mm) * 60 + float(ss)
                fo.write(f"{row['frame']},{utc_text(t + ck['offset_s'] + 1e-6 * ck['rate_ppm'] * (t - n0_s))}\n")
        if form == "rangecal_json":
            stated = {"calibration": {"rangecal_json": os.path.join(d, "out", cid, "calibration.json")}}
        else:
            stated = {"calibration": {"opencv_yml": os.path.join(d, "out", cid, "camera_opencv.yml")},
                      "sigma": {"focal_px": rms("focal_mm") / pitch_mm, "principal_point_px": rms("principal_point_px"),
                                "position_m": rms("center_enu_m"), "rotation_mrad": 1e3 * rms("rotation_rad")}}
        imported.append({
            "id": cid,
            **stated,
            "sensor": cc["sensor"],
            # the stage's own label σ and the median of its labels' timing σ (the clock's, wander included)
            "label_sigma_px": native[cid]["label_sigma_px"],
            "target_track": {"file": cc["target_track"]["file"], "timestamps": dst,
                             "readout_s": ck.get("readout_s", 0.0),
                             "timing_sigma_s": min(1.0, native[cid]["timing_sigma_s_median"])}})
    icfg.setdefault("trajectory", {})
    icfg["trajectory"] = {**icfg["trajectory"], "imported_cameras": imported}
    return icfg


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--eth-out", required=True, help="eth_drone_tracking.py's --out")
    ap.add_argument("--data", default=None, help="the eth-drone-tracking folder (default: from results.json's run)")
    ap.add_argument("--rangecal", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--datasets", default="dataset1,dataset2")
    ap.add_argument("--config-extra", default="{}", help="JSON merged into each mission (for experiments)")
    ap.add_argument("--camera-extra", default="{}",
                    help="JSON {camera name: {key: value}} merged into that camera's config (e.g. its \"free\")")
    ap.add_argument("--readout", default="", help="'estimate': each camera's rolling-shutter readout found with its clock")
    ap.add_argument("--imported", default="", choices=["", "opencv_yml", "rangecal_json"],
                    help="also run the trajectory with the cameras imported back: 'opencv_yml' (rangecal's export, "
                         "calibration.json's marginal σ stated) or 'rangecal_json' (calibration.json with its covariance)")
    ap.add_argument("--published-pp-sigma", type=float, default=0,
                    help="> 0: each camera's principal point prior from its published calibration, with this σ (px)")
    args = ap.parse_args()
    data = args.data or os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "..", "shared",
                                     "external", "eth-drone-tracking")
    results = json.load(open(os.path.join(args.eth_out, "results.json")))
    alignment = json.load(open(os.path.join(args.eth_out, "alignment.json")))
    extra = json.loads(args.config_extra)
    camera_extra = json.loads(args.camera_extra)
    os.makedirs(args.out, exist_ok=True)
    summary = {}
    for name in args.datasets.split(","):
        ds = eth.load_dataset(data, name)
        ds["track"] = track = eth.Track(ds["rtk"])
        R = results["datasets"][name]
        T0, T1 = R["common_span_s"]
        al = alignment["datasets"][name]
        ep = np.arange(track.n)
        in_span = (track.t >= T0) & (track.t <= T1) & track.good
        ep_block = np.floor((track.t - T0) / eth.BLOCK_S).astype(int)
        pooled_err, pooled_z, pooled_rows = [], [], []
        pooled_traj_err, pooled_traj_z, pooled_traj_t, pooled_traj_x = [], [], [], []
        pooled_imp_err, pooled_imp_z, pooled_imp_t = [], [], []
        summary[name] = {"splits": {}}
        for split in (0, 1):
            d = os.path.join(args.out, name, f"split{split}")
            os.makedirs(d, exist_ok=True)
            cams_cfg = []
            cam_height = {}
            for cam in ds["cams"]:
                a = al[cam["name"]]
                frames, uv = read_track_csv(os.path.join(args.eth_out, name, cam["name"], "track.csv"))
                t = a["t0_s"] + a["s"] * (frames - 1) / a["fps_nominal"]
                m = (np.floor((t - T0) / eth.BLOCK_S).astype(int) % 2) == split
                cdir = os.path.join(d, cam["name"])
                os.makedirs(cdir, exist_ok=True)
                with open(os.path.join(cdir, "track.csv"), "w") as fh:
                    fh.write("frame,u,v\n")
                    for n, (u, v) in zip(frames[m], uv[m]):
                        fh.write(f"{n},{u:.4f},{v:.4f}\n")
                with open(os.path.join(cdir, "target_track.csv"), "w") as fh:  # the held-out blocks' labels
                    fh.write("frame,u,v\n")
                    for n, (u, v) in zip(frames[~m], uv[~m]):
                        fh.write(f"{n},{u:.4f},{v:.4f}\n")
                pub = [c for c in cam["calibs"] if c["file"] == a["calibration"]][0]
                W, H = pub["res"]
                cam_height[cam["name"]] = H
                cams_cfg.append({
                    "id": cam["name"],
                    "track": {"file": os.path.join(cdir, "track.csv"),
                              "timestamps": os.path.join(args.eth_out, name, cam["name"], "timestamps.csv"),
                              "clock": "estimate", **({"readout_s": "estimate"} if args.readout else {})},
                    "target_track": {"file": os.path.join(cdir, "target_track.csv"),
                                     "timestamps": os.path.join(args.eth_out, name, cam["name"], "timestamps.csv"),
                                     "clock": "calibration"},
                    "sensor": {"width_px": W, "height_px": H, "pixel_size_um": [1.0, 1.0]},
                    "lens": {"nominal_focal_mm": pub["K"][0, 0] / 1000.0}})
                if args.published_pp_sigma > 0:
                    cams_cfg[-1]["priors"] = {"principal_point_px": [pub["K"][0, 2], pub["K"][1, 2]],
                                              "principal_point_sigma_px": args.published_pp_sigma}
            cfg = {"mission": f"ETH {name} split {split}", "site": {"origin": {"lat": 47.37, "lon": 8.55, "h": 500.0}},
                   "gnss": {"pos_files": [os.path.join(args.eth_out, name, "rtk.pos")]},
                   "lever_arm": {"vertical_m": 0.0}, "cameras": cams_cfg,
                   "align": {"max_frame_offset_s": 0.02}, "trajectory": {"rate_hz": 5},
                   "output_dir": os.path.join(d, "out")}
            for k, v in extra.items():
                cfg[k] = v if not isinstance(v, dict) else {**cfg.get(k, {}), **v}
            for cc in cfg["cameras"]:
                cc.update(camera_extra.get(cc["id"], {}))
            cfg_path = os.path.join(d, "mission.json")
            json.dump(cfg, open(cfg_path, "w"), indent=1)
            for stage in ("gnss", "align", "detect", "calibrate"):
                run([args.rangecal, stage, cfg_path])
            runj = json.load(open(os.path.join(d, "out", "run.json")))
            netj = os.path.join(d, "out", "network.json")
            img_sigma = {}
            if os.path.exists(netj):
                img_sigma = {c: v["estimated_px"] for c, v in json.load(open(netj))["statistics"].get("image_sigma", {}).items()}
            models, clocks = [], {}
            for cam in ds["cams"]:
                p, pub = opencv_camera(os.path.join(d, "out", cam["name"], "camera_opencv.yml"))
                ck = runj["stages"]["align"]["counts"][cam["name"]]["clock"]
                fps = al[cam["name"]]["fps_nominal"]
                # t(n) = n0 + off + (1 + r)((n-1)/fps - n0), n0 = first labelled frame's nominal time (s after 12:00)
                n0 = (int(read_track_csv(os.path.join(d, cam["name"], "track.csv"))[0][0]) - 1) / fps
                r = ck["rate_ppm"] * 1e-6
                p["t0"], p["ds"] = ck["offset_s"] - r * n0, ck["rate_ppm"]
                p["tau"] = ck.get("readout_s", 0.0)
                pub["fps"] = fps
                pub["height"] = cam_height[cam["name"]]
                clocks[cam["name"]] = {"t0_s": p["t0"], "rate_ppm": ck["rate_ppm"], "offset_sd_ms": ck["offset_sd_s"] * 1e3,
                                       "script_t0_s": al[cam["name"]]["t0_s"],
                                       "script_rate_ppm": (al[cam["name"]]["s"] - 1) * 1e6,
                                       "vfr": ck["variable_frame_rate"]}
                models.append((p, pub))
            hold_ep = ep[in_span & (ep_block % 2 != split)]
            rows = triangulate_epochs_rs(ds, models, hold_ep)
            err = np.array([r[1] - r[2] for r in rows])
            # predicted σ: the intersect stage on the held-out epochs as check poles
            sig = float(np.mean(list(img_sigma.values()))) if img_sigma else 1.0
            poles = os.path.join(d, "holdout_poles.csv")
            with open(poles, "w") as fh:
                fh.write("id,role,E,N,U\n")
                for r in rows:
                    fh.write(f"e{r[0]},check,{r[2][0]:.4f},{r[2][1]:.4f},{r[2][2]:.4f}\n")
            labels = [label_at_rs(cam, p, pub, track.t[[r[0] for r in rows]]) for cam, (p, pub) in zip(ds["cams"], models)]
            for k, cam in enumerate(ds["cams"]):
                with open(os.path.join(d, cam["name"] + "_holdout_px.csv"), "w") as fh:
                    fh.write("id,u,v\n")
                    for j, r in enumerate(rows):
                        if labels[k][1][j]:
                            fh.write(f"e{r[0]},{labels[k][0][j][0]:.4f},{labels[k][0][j][1]:.4f}\n")
                cfg["cameras"][k]["pole_observations"] = os.path.join(d, cam["name"] + "_holdout_px.csv")
            cfg["poles"] = poles
            cfg["intersect"] = {"pick_sigma_px": sig}
            json.dump(cfg, open(cfg_path, "w"), indent=1)
            run([args.rangecal, "intersect", cfg_path])
            ix = np.genfromtxt(os.path.join(d, "out", "intersection.csv"), delimiter=",", names=True, dtype=None, encoding=None)
            z = ix["dR"] / ix["sigma_m"]  # sigma_m = √trace: the predicted rms of dR
            # rangecal's own trajectory of the held-out blocks (the trajectory stage, 5 Hz on whole
            # seconds: the RTK's instants), each instant against the RTK fix there
            run([args.rangecal, "trajectory", cfg_path])
            hold_set = set(int(k) for k in hold_ep)
            t_err, t_z, t_parts, t_t, t_x = score_trajectory(os.path.join(d, "out", "trajectory.csv"), hold_set, track)
            if args.imported:
                # The same cameras imported back (imported_mission: their camera_opencv.yml with
                # calibration.json's marginal σ stated, or their calibration.json whole; no cross blocks)
                # and the held-out labels' times put on UTC by the clocks the align stage found.
                icfg = imported_mission(cfg, d, ds, args.eth_out, name, args.imported)
                icfg_path = os.path.join(d, "imported.json")
                json.dump(icfg, open(icfg_path, "w"), indent=1)
                run([args.rangecal, "track", icfg_path])
                ie, iz, iparts, it, _ = score_trajectory(os.path.join(d, "out_imported", "trajectory.csv"), hold_set,
                                                         track)
                irun = json.load(open(os.path.join(d, "out_imported", "run.json")))["stages"]["trajectory"]["counts"]
                conv = {c: v["imported_calibration"]["conversion_max_px"] for c, v in irun["cameras"].items()}
                pooled_imp_err.append(np.array(ie).reshape(-1, 3))
                pooled_imp_z.append(np.array(iz))
                pooled_imp_t.append(np.array(it))
                si = eth.stats_cm(np.array(ie).reshape(-1, 3))
                si["z_rms"] = float(np.sqrt(np.mean(np.square(iz)))) if iz else None
                si["median_sigma_parts_cm"] = (np.median(np.array(iparts), axis=0) * 100).tolist() if iparts else None
                si["conversion_max_px"] = conv
                s_imp = si
                print(f"{name} split {split} imported calibrations: {si['epochs']} instants, median "
                      f"{si['median_cm']:.1f} rms {si['rms_cm']:.1f} p95 {si['p95_cm']:.1f} cm; z rms {si['z_rms']:.2f}; "
                      "median σ parts (labels, timing, calibration) "
                      + " ".join(f"{v:.2f}" for v in si["median_sigma_parts_cm"]) + " cm; conversion max px "
                      + " ".join(f"{c} {v:.4f}" for c, v in conv.items()), flush=True)
            ts = eth.stats_cm(np.array(t_err).reshape(-1, 3))
            ts["z_rms"] = float(np.sqrt(np.mean(np.square(t_z)))) if t_z else None
            ts["median_sigma_parts_cm"] = (np.median(np.array(t_parts), axis=0) * 100).tolist() if t_parts else None
            pooled_traj_err.append(np.array(t_err).reshape(-1, 3))
            pooled_traj_z.append(np.array(t_z))
            pooled_traj_t.append(np.array(t_t))
            pooled_traj_x.append(np.array(t_x, bool))
            s = eth.stats_cm(err)
            s["z_rms"] = float(np.sqrt(np.mean(z ** 2)))
            s["intersect_rms_cm"] = float(np.sqrt(np.mean(ix["dR"] ** 2)) * 100)
            s["pick_sigma_px"] = sig
            s["image_sigma_px"] = img_sigma
            s["clocks"] = clocks
            s["method"] = runj["stages"]["calibrate"]["counts"].get("method_choice")
            s["trajectory"] = ts
            if args.imported:
                s["imported"] = s_imp
            summary[name]["splits"][split] = s
            pooled_err.append(err)
            pooled_z.append(z)
            print(f"{name} split {split}: {s['epochs']} epochs, median {s['median_cm']:.1f} rms {s['rms_cm']:.1f} "
                  f"p95 {s['p95_cm']:.1f} cm; z rms {s['z_rms']:.2f} (pick σ {sig:.2f} px); image σ "
                  + " ".join(f"{c} {v:.2f}" for c, v in img_sigma.items()), flush=True)
            if ts["epochs"]:
                print(f"{name} split {split} trajectory stage: {ts['epochs']} instants, median {ts['median_cm']:.1f} "
                      f"rms {ts['rms_cm']:.1f} p95 {ts['p95_cm']:.1f} cm; z rms {ts['z_rms']:.2f}; median σ parts "
                      "(labels, timing, calibration) " + " ".join(f"{v:.2f}" for v in ts["median_sigma_parts_cm"])
                      + " cm", flush=True)
        p = eth.stats_cm(np.vstack(pooled_err))
        p["z_rms"] = float(np.sqrt(np.mean(np.concatenate(pooled_z) ** 2)))
        summary[name]["pooled"] = p
        tp = eth.stats_cm(np.vstack(pooled_traj_err))
        tp["z_rms"] = float(np.sqrt(np.mean(np.concatenate(pooled_traj_z) ** 2)))
        summary[name]["pooled_trajectory"] = tp
        xs = np.concatenate(pooled_traj_x)
        keep = outside_rtk_step(name, np.concatenate(pooled_traj_t))
        hold_all = np.genfromtxt(os.path.join(args.eth_out, "holdout_epochs.csv"), delimiter=",", names=True,
                                 dtype=None, encoding=None)
        for label, sel in (("covered", ~xs & keep), ("extrapolated", xs & keep)):
            if sel.any():
                epochs = set(np.round(np.concatenate(pooled_traj_t)[sel] / eth.RTK_DT).astype(int).tolist())
                for b in ("A", "B"):
                    h = hold_all[(hold_all["dataset"] == name) & (hold_all["baseline"] == b)]
                    h = h[np.isin(h["epoch"], list(epochs))]
                    sb = eth.stats_cm(np.c_[h["dE_cm"], h["dN_cm"], h["dU_cm"]] / 100)
                    summary[name][f"baseline_{b}_{label}"] = sb
                    print(f"{name} baseline {b}, the same {label} epochs: {sb['epochs']}, median {sb['median_cm']:.1f} "
                          f"rms {sb['rms_cm']:.1f} p95 {sb['p95_cm']:.1f} cm", flush=True)
                st = eth.stats_cm(np.vstack(pooled_traj_err)[sel])
                st["z_rms"] = float(np.sqrt(np.mean(np.concatenate(pooled_traj_z)[sel] ** 2)))
                summary[name][f"pooled_trajectory_{label}"] = st
                print(f"{name} pooled trajectory stage, {label} instants (RTK step out): {st['epochs']}, median "
                      f"{st['median_cm']:.1f} rms {st['rms_cm']:.1f} p95 {st['p95_cm']:.1f} cm; z rms {st['z_rms']:.2f}",
                      flush=True)
        if name in RTK_STEP_S:
            tq = eth.stats_cm(np.vstack(pooled_traj_err)[keep])
            tq["z_rms"] = float(np.sqrt(np.mean(np.concatenate(pooled_traj_z)[keep] ** 2)))
            summary[name]["pooled_trajectory_without_rtk_step"] = tq
            print(f"{name} pooled trajectory stage without the RTK step {RTK_STEP_S[name]}: {tq['epochs']} instants, "
                  f"median {tq['median_cm']:.1f} rms {tq['rms_cm']:.1f} p95 {tq['p95_cm']:.1f} cm; "
                  f"z rms {tq['z_rms']:.2f}", flush=True)
            hold = np.genfromtxt(os.path.join(args.eth_out, "holdout_epochs.csv"), delimiter=",", names=True,
                                 dtype=None, encoding=None)
            for b in ("A", "B"):
                h = hold[(hold["dataset"] == name) & (hold["baseline"] == b)]
                e = np.c_[h["dE_cm"], h["dN_cm"], h["dU_cm"]] / 100
                k2 = outside_rtk_step(name, h["t_s"])
                sb = eth.stats_cm(e[k2])
                summary[name][f"baseline_{b}_without_rtk_step"] = sb
                print(f"{name} baseline {b} without the RTK step: {sb['epochs']} epochs, median {sb['median_cm']:.1f} "
                      f"rms {sb['rms_cm']:.1f} p95 {sb['p95_cm']:.1f} cm", flush=True)
        if pooled_imp_err:
            ti = eth.stats_cm(np.vstack(pooled_imp_err))
            ti["z_rms"] = float(np.sqrt(np.mean(np.concatenate(pooled_imp_z) ** 2)))
            summary[name]["pooled_imported"] = ti
            print(f"{name} pooled imported calibrations: {ti['epochs']} instants, median {ti['median_cm']:.1f} rms "
                  f"{ti['rms_cm']:.1f} p95 {ti['p95_cm']:.1f} cm; z rms {ti['z_rms']:.2f}", flush=True)
            if name in RTK_STEP_S:
                ki = outside_rtk_step(name, np.concatenate(pooled_imp_t))
                tj = eth.stats_cm(np.vstack(pooled_imp_err)[ki])
                tj["z_rms"] = float(np.sqrt(np.mean(np.concatenate(pooled_imp_z)[ki] ** 2)))
                summary[name]["pooled_imported_without_rtk_step"] = tj
                print(f"{name} pooled imported calibrations without the RTK step: {tj['epochs']} instants, median "
                      f"{tj['median_cm']:.1f} rms {tj['rms_cm']:.1f} cm; z rms {tj['z_rms']:.2f}", flush=True)
        print(f"{name} pooled trajectory stage: {tp['epochs']} instants, median {tp['median_cm']:.1f} rms "
              f"{tp['rms_cm']:.1f} p95 {tp['p95_cm']:.1f} cm; z rms {tp['z_rms']:.2f}", flush=True)
        print(f"{name} pooled: {p['epochs']} epochs, median {p['median_cm']:.1f} rms {p['rms_cm']:.1f} "
              f"p95 {p['p95_cm']:.1f} cm; z rms {p['z_rms']:.2f}", flush=True)
    json.dump(summary, open(os.path.join(args.out, "rangecal_results.json"), "w"), indent=1, default=str)


if __name__ == "__main__":
    main()

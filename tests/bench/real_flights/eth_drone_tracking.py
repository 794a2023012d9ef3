#!/usr/bin/env python3
"""Real-data accuracy benchmark on the ETH Zurich multi-view drone-tracking datasets 1 and 2.

Independent of rangecal's C++ code on purpose: these are the baselines rangecal's default must
beat, so they must not share its bugs. See README.md beside this file for the protocol, how to
run it and the figures it measured.

Data: Li, Murray, Ismaili, Schindler, Albl, "Reconstruction of 3D flight trajectories from ad-hoc
camera networks", arXiv 2003.04784; CC BY-NC-SA 4.0. It is read from --data (outside the
repository) and never copied into it; the exports in --out are derived data under the same licence.
"""
import argparse
import datetime
import json
import math
import os
import sys

# One thread: other engineers compile on this 2-core machine, and the loops here are small.
for _v in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

try:
    import numpy as np
    import cv2
    from scipy.interpolate import CubicSpline
    from scipy.optimize import least_squares
except ImportError:
    # A pyenv/venv python3 first on PATH hides the Debian packages the README asks for; rerun
    # once under the system interpreter rather than asking for pip.
    if os.path.exists("/usr/bin/python3") and os.path.realpath(sys.executable) != os.path.realpath("/usr/bin/python3") \
            and not os.environ.get("ETH_BENCH_REEXEC"):
        os.environ["ETH_BENCH_REEXEC"] = "1"
        os.execv("/usr/bin/python3", ["/usr/bin/python3"] + sys.argv)
    sys.exit("needs numpy, scipy and OpenCV: apt-get install -y python3-numpy python3-scipy python3-opencv")

cv2.setNumThreads(1)

RTK_DT = 0.2          # s; SOURCE.md: the track has no time column and is read at 5 Hz
BLOCK_S = 20.0        # s; hold-out block length
ACC_GLITCH = 10.0     # m/s^2; a 5 Hz RTK track of this hexacopter never accelerates this hard
                      # (dataset 1 p99 is 3.6 m/s^2): above it the fix jumped (dataset 2's first 40 s)
HUBER_PX = 2.0        # px; hand labels are ~1 px, so residuals beyond 2 px are down-weighted
COARSE_STEP = 0.2     # s; at <= 6 m/s the drone moves <= 1.2 m per step, well inside the score's basin
TRUNC_PX = 25.0       # px; truncation of the coarse score, so that wrong offsets cannot win on outliers


# ----------------------------------------------------------------------------------------------
# reading
# ----------------------------------------------------------------------------------------------

def read_numeric_rows(path):
    """Rows of floats; header lines (some files have one, some not) are skipped."""
    rows = []
    with open(path) as fh:
        for line in fh:
            parts = line.split()
            if not parts or line.lstrip().startswith("#"):
                continue
            try:
                rows.append([float(x) for x in parts])
            except ValueError:
                continue
    return np.array(rows)


def read_calibration(path):
    with open(path) as fh:
        j = json.load(fh)
    K = np.array(j["K-matrix"], float)
    d = np.zeros(5)
    d[:len(j["distCoeff"])] = j["distCoeff"]   # sonyG_1 gives only [k1 k2 p1 p2]
    return {"file": os.path.relpath(path, os.path.dirname(os.path.dirname(os.path.dirname(path)))),
            "K": K, "dist": d, "fps": float(j["fps"]), "res": tuple(j["resolution"])}


def load_dataset(root, name):
    ds = {"name": name}
    ds["rtk"] = read_numeric_rows(os.path.join(root, name, "trajectory", "rtk.txt"))[:, :3]
    cams = []
    with open(os.path.join(root, name, "cameras.txt")) as fh:
        for line in fh:
            if "-" not in line:
                continue
            cam, dev = [s.strip() for s in line.split("-", 1)]
            cdir = os.path.join(root, "calibration", dev)
            calibs = [read_calibration(os.path.join(cdir, f)) for f in sorted(os.listdir(cdir)) if f.endswith(".json")]
            a = read_numeric_rows(os.path.join(root, name, "detections", cam + ".txt"))
            lab = (a[:, 1] != 0) | (a[:, 2] != 0)      # "0 0" = no label
            cams.append({"name": cam, "device": dev, "calibs": calibs,
                         "n": a[lab, 0].astype(int), "uv": a[lab, 1:3].copy(), "n_frames": int(a[:, 0].max())})
    ds["cams"] = cams
    return ds


# ----------------------------------------------------------------------------------------------
# the RTK track
# ----------------------------------------------------------------------------------------------

class Track:
    """RTK positions at t_i = 0.2 i s, interpolated by a cubic spline.

    Cubic, not linear: the drone turns at up to ~3.5 m/s^2, so linear interpolation between 5 Hz
    fixes errs by up to a*dt^2/8 ~ 2 cm, a cubic by well under 1 mm; and a C2 spline gives the
    alignment a reprojection error that is smooth in t0 (linear interpolation has kinks at every
    fix, which stall a least-squares search on t0). Epochs near a glitch (implausible
    acceleration) are marked bad, and frames whose spline support touches one are not used.
    """

    def __init__(self, enu):
        self.p = enu
        self.n = len(enu)
        self.t = np.arange(self.n) * RTK_DT
        self.T = self.t[-1]
        self.spline = CubicSpline(self.t, enu, axis=0)
        acc = np.linalg.norm(np.diff(enu, 2, axis=0), axis=1) / RTK_DT ** 2
        bad = np.zeros(self.n, bool)
        for i in np.where(acc > ACC_GLITCH)[0]:
            bad[max(0, i - 2):i + 5] = True   # the jump and the spline's ringing around it
        self.good = ~bad

    def at(self, t):
        tc = np.clip(t, 0.0, self.T)
        i = np.floor(tc / RTK_DT).astype(int)
        ok = (t >= 0) & (t <= self.T)
        for d in (-1, 0, 1, 2):
            ok &= self.good[np.clip(i + d, 0, self.n - 1)]
        return self.spline(tc), ok


# ----------------------------------------------------------------------------------------------
# camera model: OpenCV's pinhole + Brown distortion, so the published calibrations apply as is
# ----------------------------------------------------------------------------------------------
# A parameter set is a dict: rx ry rz (Rodrigues, world->camera), tx ty tz, and either the
# published intrinsics (model "B") or f, cx, cy, k1, k2 (model "A", fy = f * published fy/fx,
# p1 = p2 = k3 = 0); time: t0 (s after the first RTK fix), ds (clock-rate error, ppm) and tau
# (rolling-shutter readout, s, only in the alignment report).

TIME_KEYS = ["t0", "ds", "tau"]
POSE_KEYS = ["rx", "ry", "rz", "tx", "ty", "tz"]
INTR_KEYS = ["f", "cx", "cy", "k1", "k2"]
SCALE = {"rx": 1e-3, "ry": 1e-3, "rz": 1e-3, "tx": 0.05, "ty": 0.05, "tz": 0.05, "f": 10.0,
         "cx": 5.0, "cy": 5.0, "k1": 0.01, "k2": 0.01, "t0": 0.005, "ds": 20.0, "tau": 0.005}


def intrinsics(p, pub):
    if p["model"] == "B":
        return pub["K"], pub["dist"]
    K = np.array([[p["f"], 0, p["cx"]], [0, p["f"] * pub["K"][1, 1] / pub["K"][0, 0], p["cy"]], [0, 0, 1.0]])
    return K, np.array([p["k1"], p["k2"], 0, 0, 0.0])


def project(X, p, pub):
    K, d = intrinsics(p, pub)
    rv = np.array([p["rx"], p["ry"], p["rz"]])
    tv = np.array([p["tx"], p["ty"], p["tz"]])
    uv, _ = cv2.projectPoints(np.ascontiguousarray(X, float).reshape(-1, 1, 3), rv, tv, K, d)
    return uv.reshape(-1, 2)


def frame_time(n, v, p, fps, height):
    """t = t0 + (1 + ds 1e-6) (n - 1)/fps, plus the rolling-shutter row delay tau (v/(H-1) - 1/2)."""
    return p["t0"] + (1.0 + p["ds"] * 1e-6) * (n - 1) / fps + p.get("tau", 0.0) * (v / (height - 1) - 0.5)


def epoch_to_frame(t, p, fps):
    return (t - p["t0"]) / (1.0 + p["ds"] * 1e-6) * fps + 1.0


def fit(obs_n, obs_uv, p0, free, track, pub, loss="huber"):
    """Least squares on the reprojection error of (RTK(frame time), label) pairs.

    Returns the parameters, the residuals (px), the robust sigma and the parameters' 1-sigma
    from the Gauss-Newton Hessian (white-noise assumption: optimistic, the labels' errors are
    correlated from frame to frame)."""
    fps, H = pub["fps"], pub["res"][1]
    t_init = frame_time(obs_n, obs_uv[:, 1], p0, fps, H)
    _, ok = track.at(t_init)          # fixed observation set: no frame drops in and out mid-fit
    n, uv = obs_n[ok], obs_uv[ok]
    x0 = np.array([p0[k] for k in free])
    scale = np.array([SCALE[k] for k in free])

    def unpack(x):
        p = dict(p0)
        p.update(zip(free, x))
        return p

    def res(x):
        p = unpack(x)
        X, _ = track.at(frame_time(n, uv[:, 1], p, fps, H))
        return (project(X, p, pub) - uv).ravel()

    r = least_squares(res, x0, x_scale=scale, loss=loss, f_scale=HUBER_PX, method="trf", max_nfev=200 * len(x0))
    p = unpack(r.x)
    e = r.fun.reshape(-1, 2)
    en = np.linalg.norm(e, axis=1)
    sig = 1.4826 * np.median(np.abs(r.fun))
    try:
        J = r.jac
        cov = np.linalg.inv(J.T @ J) * sig ** 2
        sd = dict(zip(free, np.sqrt(np.diag(cov))))
    except np.linalg.LinAlgError:
        sd = {k: float("nan") for k in free}
    return {"p": p, "sd": sd, "n": n, "uv": uv, "err": en, "rms": float(np.sqrt(np.mean(en ** 2))),
            "rms_in": float(np.sqrt(np.mean(en[en < 5 * max(sig, 0.3)] ** 2))), "sigma": float(sig),
            "n_obs": int(len(n)), "n_out": int(np.sum(en >= 5 * max(sig, 0.3)))}


# ----------------------------------------------------------------------------------------------
# 1. time alignment
# ----------------------------------------------------------------------------------------------

def pnp_score(t0, n, uv, track, pub):
    """Truncated mean squared reprojection error of a RANSAC PnP at offset t0 (published K, d)."""
    X, ok = track.at(t0 + (n - 1) / pub["fps"])
    if ok.sum() < 0.7 * len(n):
        return TRUNC_PX ** 2, None
    try:
        found, rv, tv, inl = cv2.solvePnPRansac(X[ok], uv[ok], pub["K"], pub["dist"], iterationsCount=100,
                                                reprojectionError=10.0, confidence=0.99, flags=cv2.SOLVEPNP_EPNP)
    except cv2.error:
        return TRUNC_PX ** 2, None
    if not found or inl is None or len(inl) < 6:
        return TRUNC_PX ** 2, None
    # refine on the inliers, then score every point (points outside the track count as truncated)
    rv, tv = cv2.solvePnPRefineLM(X[ok][inl[:, 0]], uv[ok][inl[:, 0]], pub["K"], pub["dist"], rv, tv)
    e = np.linalg.norm(cv2.projectPoints(X[ok], rv, tv, pub["K"], pub["dist"])[0].reshape(-1, 2) - uv[ok], axis=1)
    e2 = np.minimum(e, TRUNC_PX) ** 2
    return (e2.sum() + (len(n) - ok.sum()) * TRUNC_PX ** 2) / len(n), (rv.ravel(), tv.ravel())


def align_camera(cam, pub, track, log):
    n, uv = cam["n"], cam["uv"]
    fps = pub["fps"]
    sub = np.linspace(0, len(n) - 1, min(200, len(n))).astype(int)
    ns, uvs = n[sub], uv[sub]
    span = (ns[-1] - ns[0]) / fps
    lo = -(ns[0] - 1) / fps - 0.3 * span
    hi = track.T - (ns[-1] - 1) / fps + 0.3 * span
    grid = np.arange(lo, hi, COARSE_STEP)
    scores = np.array([pnp_score(t, ns, uvs, track, pub)[0] for t in grid])
    ib = int(np.argmin(scores))
    # second-best basin more than 2 s away: a measure of how unambiguous the offset is
    far = np.abs(grid - grid[ib]) > 2.0
    second = float(np.sqrt(scores[far].min())) if far.any() else float("nan")
    fine = np.arange(grid[ib] - 0.4, grid[ib] + 0.4, 0.01)
    fs = [pnp_score(t, ns, uvs, track, pub) for t in fine]
    jf = int(np.argmin([s for s, _ in fs]))
    t0c, pose = fine[jf], fs[jf][1]
    log(f"    coarse t0 {grid[ib]:8.2f} s (trunc-rms {math.sqrt(scores[ib]):5.1f} px, best other basin "
        f"{second:5.1f} px), fine {t0c:8.2f} s ({math.sqrt(fs[jf][0]):5.2f} px), {len(grid) + len(fine)} PnPs")
    K = pub["K"]
    p = {"model": "A", "rx": pose[0][0], "ry": pose[0][1], "rz": pose[0][2], "tx": pose[1][0], "ty": pose[1][1],
         "tz": pose[1][2], "f": K[0, 0], "cx": K[0, 2], "cy": K[1, 2], "k1": pub["dist"][0], "k2": pub["dist"][1],
         "t0": t0c, "ds": 0.0, "tau": 0.0}
    # published-intrinsics (B) fit first: a robust start for the pose, then everything free (A)
    pb = dict(p, model="B")
    fb = fit(n, uv, pb, POSE_KEYS + ["t0", "ds"], track, pub)
    p.update({k: fb["p"][k] for k in POSE_KEYS + ["t0", "ds"]})
    fa = fit(n, uv, p, POSE_KEYS + INTR_KEYS + ["t0", "ds"], track, pub)
    # rolling shutter: the same fit with a readout time; its sign says whether lower rows are later
    fr = fit(n, uv, dict(fa["p"]), POSE_KEYS + INTR_KEYS + ["t0", "ds", "tau"], track, pub)
    return {"coarse_t0": float(grid[ib]), "coarse_rms": float(math.sqrt(scores[ib])), "second_basin_rms": second,
            "curve": (grid, np.sqrt(scores)), "B": fb, "A": fa, "RS": fr}


def block_offsets(cam, fa, pub, track):
    """Offset of each 20-s block of the camera's record, everything else fixed at the global fit.

    With a constant frame rate these lie on a line of slope 0 (ds already fitted); a variable
    frame rate (phones) shows as steps or curvature."""
    p = fa["p"]
    t = frame_time(fa["n"], fa["uv"][:, 1], p, pub["fps"], pub["res"][1])
    b = np.floor((t - t[0]) / BLOCK_S).astype(int)
    out = []
    for k in np.unique(b):
        m = b == k
        if m.sum() < 60:
            continue
        r = fit(fa["n"][m], fa["uv"][m], dict(p), ["t0"], track, pub)
        out.append((float(np.mean(t[m])), (r["p"]["t0"] - p["t0"]) * 1e3, r["sd"]["t0"] * 1e3, int(m.sum())))
    return out


# ----------------------------------------------------------------------------------------------
# triangulation
# ----------------------------------------------------------------------------------------------

def label_at(cam, p, fps, t):
    """The 2-D label at instant t, linearly interpolated between the two frames around it.

    Interpolated rather than nearest: at 25-30 fps the nearest frame is up to 17-20 ms off, i.e.
    up to 10 cm of drone motion at 5 m/s. Both neighbours must be labelled."""
    phi = epoch_to_frame(t, p, fps)
    n0 = np.floor(phi).astype(int)
    idx = np.full(cam["n_frames"] + 2, -1)
    idx[cam["n"]] = np.arange(len(cam["n"]))
    ok = (n0 >= 1) & (n0 + 1 <= cam["n_frames"])
    a = np.where(ok, idx[np.clip(n0, 0, cam["n_frames"] + 1)], -1)
    b = np.where(ok, idx[np.clip(n0 + 1, 0, cam["n_frames"] + 1)], -1)
    ok &= (a >= 0) & (b >= 0)
    w = (phi - n0)[:, None]
    uv = (1 - w) * cam["uv"][np.maximum(a, 0)] + w * cam["uv"][np.maximum(b, 0)]
    return uv, ok


def triangulate(obs):
    """obs: list of (uv, p, pub). Linear DLT on undistorted normalised points, then Gauss-Newton on
    the pixel reprojection error with the full camera model."""
    A = []
    for uv, p, pub in obs:
        K, d = intrinsics(p, pub)
        x = cv2.undistortPoints(uv.reshape(1, 1, 2), K, d).ravel()
        R, _ = cv2.Rodrigues(np.array([p["rx"], p["ry"], p["rz"]]))
        P = np.hstack([R, np.array([[p["tx"]], [p["ty"]], [p["tz"]]])])
        A.append(x[0] * P[2] - P[0])
        A.append(x[1] * P[2] - P[1])
    _, _, Vt = np.linalg.svd(np.array(A))
    X0 = Vt[-1, :3] / Vt[-1, 3]

    def res(X):
        return np.concatenate([project(X[None], p, pub)[0] - uv for uv, p, pub in obs])

    r = least_squares(res, X0, method="lm")
    return r.x, float(np.sqrt(np.mean(r.fun ** 2)))


def triangulate_epochs(ds, models, epochs):
    """For each RTK epoch index: the triangulated point from every camera with a label there."""
    track = ds["track"]
    labels = []
    for cam, (p, pub) in zip(ds["cams"], models):
        labels.append(label_at(cam, p, pub["fps"], track.t[epochs]))
    rows = []
    for j, e in enumerate(epochs):
        obs = [(lab[0][j], p, pub) for lab, (p, pub) in zip(labels, models) if lab[1][j]]
        if len(obs) < 2:
            continue
        X, rms = triangulate(obs)
        # widest angle between two rays: small angles (cameras nearly in line with the drone)
        # are where a few px become decimetres along the ray
        cen = []
        for _, p, _ in obs:
            R, _ = cv2.Rodrigues(np.array([p["rx"], p["ry"], p["rz"]]))
            cen.append(-R.T @ np.array([p["tx"], p["ty"], p["tz"]]))
        ray = [(X - c) / np.linalg.norm(X - c) for c in cen]
        ang = max(math.degrees(math.acos(min(1.0, abs(float(a @ b))))) for i, a in enumerate(ray) for b in ray[i + 1:])
        rows.append((e, X, track.p[e], len(obs), rms, ang, "+".join(str(k) for k, lab in enumerate(labels) if lab[1][j])))
    return rows


def stats_cm(err):
    e = np.linalg.norm(err, axis=1) * 100
    if len(e) == 0:
        return {"epochs": 0}
    return {"epochs": int(len(e)), "median_cm": float(np.median(e)), "rms_cm": float(np.sqrt(np.mean(e ** 2))),
            "p95_cm": float(np.percentile(e, 95)), "max_cm": float(e.max()), "over_50cm": int(np.sum(e > 50))}


# ----------------------------------------------------------------------------------------------
# 6. exports for rangecal
# ----------------------------------------------------------------------------------------------

WGS84_A = 6378137.0
WGS84_F = 1 / 298.257223563
WGS84_E2 = WGS84_F * (2 - WGS84_F)


def geodetic_to_ecef(lat, lon, h):
    la, lo = math.radians(lat), math.radians(lon)
    N = WGS84_A / math.sqrt(1 - WGS84_E2 * math.sin(la) ** 2)
    return np.array([(N + h) * math.cos(la) * math.cos(lo), (N + h) * math.cos(la) * math.sin(lo),
                     (N * (1 - WGS84_E2) + h) * math.sin(la)])


def ecef_to_geodetic(x, y, z):
    """Exact to < 1e-10 m after a few fixed-point iterations at these heights."""
    lon = np.arctan2(y, x)
    p = np.hypot(x, y)
    lat = np.arctan2(z, p * (1 - WGS84_E2))
    for _ in range(10):
        N = WGS84_A / np.sqrt(1 - WGS84_E2 * np.sin(lat) ** 2)
        h = p / np.cos(lat) - N
        lat = np.arctan2(z, p * (1 - WGS84_E2 * N / (N + h)))
    N = WGS84_A / np.sqrt(1 - WGS84_E2 * np.sin(lat) ** 2)
    h = p / np.cos(lat) - N
    return np.degrees(lat), np.degrees(lon), h


def enu_to_geodetic(enu, lat0, lon0, h0):
    """Local tangent plane at (lat0, lon0, h0) on WGS84: ECEF = ECEF0 + R^T enu."""
    la, lo = math.radians(lat0), math.radians(lon0)
    R = np.array([[-math.sin(lo), math.cos(lo), 0],
                  [-math.sin(la) * math.cos(lo), -math.sin(la) * math.sin(lo), math.cos(la)],
                  [math.cos(la) * math.cos(lo), math.cos(la) * math.sin(lo), math.sin(la)]])
    ecef = geodetic_to_ecef(lat0, lon0, h0)[None] + enu @ R
    return ecef_to_geodetic(ecef[:, 0], ecef[:, 1], ecef[:, 2])


UTC0 = datetime.datetime(2020, 1, 1, 12, 0, 0, tzinfo=datetime.timezone.utc)


def utc_str(t, iso):
    ns = int(round(t * 1e9))
    dt = UTC0 + datetime.timedelta(microseconds=ns // 1000)
    if iso:
        return dt.strftime("%Y-%m-%dT%H:%M:%S") + f".{ns % 1_000_000_000:09d}Z"
    return dt.strftime("%Y/%m/%d %H:%M:%S") + f".{(ns // 1_000_000) % 1000:03d}"


def export(ds, out, origin, alignment):
    d = os.path.join(out, ds["name"])
    os.makedirs(d, exist_ok=True)
    track = ds["track"]
    lat, lon, h = enu_to_geodetic(track.p, *origin)
    with open(os.path.join(d, "rtk.pos"), "w") as fh:
        fh.write("% program   : eth_drone_tracking.py (rangecal real-flight benchmark), from rtk.txt read at 5 Hz\n")
        # No `ref pos` line: RTKLIB writes one only for relative (base-rover) output, as ECEF.
        fh.write(f"% ENU origin of rtk.txt (chosen): {origin[0]:.9f} {origin[1]:.9f} {origin[2]:.4f}\n")
        fh.write("% data      : ETH drone-tracking dataset (arXiv 2003.04784), CC BY-NC-SA 4.0; UTC start arbitrary\n")
        fh.write("%\n%  UTC                   latitude(deg) longitude(deg)  height(m)   Q  ns   sdn(m)   sde(m)   sdu(m)"
                 "  sdne(m)  sdeu(m)  sdun(m) age(s)  ratio\n")
        for i in range(track.n):
            fh.write(f"{utc_str(track.t[i], False)}  {lat[i]:14.9f} {lon[i]:14.9f} {h[i]:10.4f}   1  10"
                     f"   0.0200   0.0200   0.0200   0.0000   0.0000   0.0000   0.00    0.0\n")
    for cam, a in zip(ds["cams"], alignment):
        cd = os.path.join(d, cam["name"])
        os.makedirs(cd, exist_ok=True)
        with open(os.path.join(cd, "track.csv"), "w") as fh:
            fh.write("frame,u,v\n")
            for n, (u, v) in zip(cam["n"], cam["uv"]):
                fh.write(f"{n},{u:.4f},{v:.4f}\n")
        # nominal times: the RTK start plus (n-1)/fps, so the offset t0 stays unknown to rangecal
        with open(os.path.join(cd, "timestamps.csv"), "w") as fh:
            fh.write("frame,utc\n")
            for n in range(1, cam["n_frames"] + 1):
                fh.write(f"{n},{utc_str((n - 1) / a['fps'], True)}\n")


# ----------------------------------------------------------------------------------------------
# main
# ----------------------------------------------------------------------------------------------

def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", required=True, help="the eth-drone-tracking folder (read-only)")
    ap.add_argument("--out", required=True, help="output folder (results.json, exports)")
    ap.add_argument("--datasets", default="dataset1,dataset2")
    ap.add_argument("--origin", default="47.37,8.55,500", help="lat,lon,h of the ENU origin for the .pos export")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    origin = tuple(float(x) for x in args.origin.split(","))
    logf = open(os.path.join(args.out, "log.txt"), "w")

    def log(s):
        print(s, flush=True)
        logf.write(s + "\n")

    results = {"data": "Li, Murray, Ismaili, Schindler, Albl, arXiv 2003.04784 (CC BY-NC-SA 4.0)",
               "rtk_rate_hz": 1 / RTK_DT, "block_s": BLOCK_S, "datasets": {}}
    alignment_json = {"note": "t0_s: instant of frame 1 in seconds after the first RTK fix (= 2020-01-01T12:00:00Z "
                              "in rtk.pos); frame n is at t0 + s (n-1)/fps. timestamps.csv carries t0 = 0, s = 1.",
                      "datasets": {}}
    epoch_lines = ["dataset,split,baseline,epoch,t_s,cameras,n_cameras,max_ray_angle_deg,rms_px,dE_cm,dN_cm,dU_cm,err_offset_removed_cm"]
    for name in args.datasets.split(","):
        ds = load_dataset(args.data, name)
        ds["track"] = track = Track(ds["rtk"])
        log(f"== {name}: RTK {track.n} fixes = {track.T:.1f} s, {np.sum(~track.good)} marked as glitches")
        R = {"cameras": {}, "holdout": {}}
        align = []
        for cam in ds["cams"]:
            log(f"  {cam['name']} ({cam['device']}): {len(cam['n'])} labelled of {cam['n_frames']} frames")
            best = None
            for pub in cam["calibs"]:
                log(f"   calibration {pub['file']}")
                a = align_camera(cam, pub, track, log)
                log(f"    B (published K, d): rms {a['B']['rms']:.2f} px, robust sigma {a['B']['sigma']:.2f} px; "
                    f"A (f,c,k1,k2 free): rms {a['A']['rms']:.2f} px, sigma {a['A']['sigma']:.2f}, "
                    f"f {a['A']['p']['f']:.1f} (published {pub['K'][0, 0]:.1f})")
                a["pub"] = pub
                if best is None or a["B"]["sigma"] < best["B"]["sigma"]:
                    best = a
                cam.setdefault("tried", []).append(
                    {"calibration": pub["file"], "B_rms_px": a["B"]["rms"], "B_sigma_px": a["B"]["sigma"],
                     "A_rms_px": a["A"]["rms"], "A_sigma_px": a["A"]["sigma"], "A_f": a["A"]["p"]["f"]})
            a, pub = best, best["pub"]
            fa, fr = a["A"], a["RS"]
            blocks = block_offsets(cam, fa, pub, track)
            bo = np.array([b[1] for b in blocks])
            bs = np.array([b[2] for b in blocks])
            bt = np.array([b[0] for b in blocks])
            # variable frame rate: block offsets off a straight line by much more than their sigma
            # Flag: a well-determined block (sigma <= 3 ms) more than 8 ms off the weighted line.
            # The threshold comes from the two constant-rate Sony cameras, whose well-determined
            # blocks stay within 5.4 ms: a block's offset also absorbs a px or so of systematic
            # reprojection error (rolling shutter, distortion) along the drone's motion there, and
            # the Hessian sigma is optimistic, so a chi-square on it flags every camera.
            if len(bo) >= 3:
                c = np.polyfit(bt, bo, 1, w=1 / np.maximum(bs, 0.2))
                dev = bo - np.polyval(c, bt)
                chi2 = float(np.sum((dev / np.maximum(bs, 1e-3)) ** 2) / (len(bo) - 2))
                vfr = bool(np.any((np.abs(dev) > 8.0) & (bs <= 3.0)))
            else:
                dev, chi2, vfr = np.zeros(0), float("nan"), False
            s_k = 1 + fa["p"]["ds"] * 1e-6
            info = {"device": cam["device"], "calibration_used": pub["file"], "tried": cam["tried"],
                    "fps_nominal": pub["fps"], "labelled": int(len(cam["n"])), "frames": cam["n_frames"],
                    "t0_s": float(fa["p"]["t0"]), "t0_sigma_hessian_s": float(fa["sd"]["t0"]),
                    "t0_sigma_blocks_s": float(np.std(dev, ddof=2) / math.sqrt(len(dev)) * 1e-3) if len(dev) > 2 else None,
                    "s": float(s_k), "s_sigma": float(fa["sd"]["ds"] * 1e-6),
                    "coarse_t0_s": a["coarse_t0"], "coarse_trunc_rms_px": a["coarse_rms"],
                    "second_basin_trunc_rms_px": a["second_basin_rms"],
                    "residual_rms_px": fa["rms"], "residual_rms_inliers_px": fa["rms_in"],
                    "residual_robust_sigma_px": fa["sigma"], "outliers_5sigma": fa["n_out"], "used": fa["n_obs"],
                    "A_intrinsics": {k: float(fa["p"][k]) for k in INTR_KEYS},
                    "A_intrinsics_sigma": {k: float(fa["sd"][k]) for k in INTR_KEYS},
                    "B_residual_rms_px": a["B"]["rms"], "B_robust_sigma_px": a["B"]["sigma"],
                    "B_t0_s": float(a["B"]["p"]["t0"]), "B_s": float(1 + a["B"]["p"]["ds"] * 1e-6),
                    "rolling_shutter_tau_s": float(fr["p"]["tau"]), "rolling_shutter_tau_sigma_s": float(fr["sd"]["tau"]),
                    "rolling_shutter_sigma_px": fr["sigma"],
                    "block_offsets_ms": [{"t_s": b[0], "offset_ms": b[1], "sigma_ms": b[2], "frames": b[3]} for b in blocks],
                    "block_nonlinearity_max_ms": float(np.max(np.abs(dev))) if len(dev) else None,
                    "block_chi2_per_dof": chi2, "variable_frame_rate_flag": vfr}
            R["cameras"][cam["name"]] = info
            cam["pub"], cam["align"] = pub, fa["p"]
            align.append({"fps": pub["fps"]})
            log(f"   => t0 {info['t0_s']:.4f} s ± {info['t0_sigma_hessian_s'] * 1e3:.2f} ms (Hessian), "
                f"s-1 {fa['p']['ds']:+.1f} ± {fa['sd']['ds']:.1f} ppm, rms {fa['rms']:.2f} px (inliers {fa['rms_in']:.2f}), "
                f"tau {fr['p']['tau'] * 1e3:+.1f} ± {fr['sd']['tau'] * 1e3:.1f} ms, block offsets off a line by up to "
                f"{info['block_nonlinearity_max_ms']:.1f} ms, VFR {vfr}")
            log("    block offsets (ms): " + " ".join(f"{b[1]:+.1f}±{b[2]:.1f}" for b in blocks))

        # ---- 2. hold-out blocks on the common flight time (where >= 2 cameras record)
        spans = []
        for cam in ds["cams"]:
            t = frame_time(cam["n"], cam["uv"][:, 1], cam["align"], cam["pub"]["fps"], cam["pub"]["res"][1])
            spans.append((t.min(), t.max()))
        starts, ends = sorted(s for s, _ in spans), sorted(e for _, e in spans)
        T0, T1 = starts[1], ends[-2]
        R["common_span_s"] = [float(T0), float(T1)]
        log(f"  common span (>= 2 cameras) {T0:.1f}-{T1:.1f} s, {int(math.ceil((T1 - T0) / BLOCK_S))} blocks of {BLOCK_S:.0f} s")
        ep = np.arange(track.n)
        in_span = (track.t >= T0) & (track.t <= T1) & track.good
        ep_block = np.floor((track.t - T0) / BLOCK_S).astype(int)
        pooled = {"A": [], "B": []}
        pooled_wide = {"A": [], "B": []}
        pooled_off = {"A": [], "B": []}
        for split in (0, 1):
            cal_parity = split          # split 0: even blocks calibrate; split 1: odd blocks calibrate
            models = {"A": [], "B": []}
            for cam in ds["cams"]:
                pub = cam["pub"]
                t = frame_time(cam["n"], cam["uv"][:, 1], cam["align"], pub["fps"], pub["res"][1])
                m = (np.floor((t - T0) / BLOCK_S).astype(int) % 2) == cal_parity
                pa = dict(cam["align"], tau=0.0)
                fa = fit(cam["n"][m], cam["uv"][m], pa, POSE_KEYS + INTR_KEYS + ["t0", "ds"], track, pub)
                fb = fit(cam["n"][m], cam["uv"][m], dict(pa, model="B"), POSE_KEYS + ["t0", "ds"], track, pub)
                models["A"].append((fa["p"], pub))
                models["B"].append((fb["p"], pub))
                R["cameras"][cam["name"]].setdefault("splits", []).append(
                    {"split": split, "frames": int(m.sum()), "A_rms_px": fa["rms"], "B_rms_px": fb["rms"],
                     "A_t0_s": float(fa["p"]["t0"]), "B_t0_s": float(fb["p"]["t0"]),
                     "A_f": float(fa["p"]["f"]), "A_cx": float(fa["p"]["cx"]), "A_cy": float(fa["p"]["cy"]),
                     "A_k1": float(fa["p"]["k1"]), "A_k2": float(fa["p"]["k2"])})
            cal_ep = ep[in_span & (ep_block % 2 == cal_parity)]
            hold_ep = ep[in_span & (ep_block % 2 != cal_parity)]
            for base in ("A", "B"):
                cal_rows = triangulate_epochs(ds, models[base], cal_ep)
                hold_rows = triangulate_epochs(ds, models[base], hold_ep)
                # constant ENU offset (label vs antenna lever arm, mean over attitudes) from the
                # calibration blocks only
                off = np.median(np.array([r[1] - r[2] for r in cal_rows]), axis=0)
                err = np.array([r[1] - r[2] for r in hold_rows])
                s_raw, s_off = stats_cm(err), stats_cm(err - off)
                ncam = np.array([r[3] for r in hold_rows])
                R["holdout"].setdefault(base, {})[f"split{split}"] = {
                    "raw": s_raw, "offset_removed": s_off, "offset_enu_cm": (off * 100).tolist(),
                    "epochs_by_cameras": {str(k): int(np.sum(ncam == k)) for k in range(2, 5)}}
                for r, eo in zip(hold_rows, err - off):
                    epoch_lines.append(f"{name},{split},{base},{r[0]},{track.t[r[0]]:.1f},{r[6]},{r[3]},{r[5]:.2f},{r[4]:.3f},"
                                       f"{(r[1][0] - r[2][0]) * 100:.2f},{(r[1][1] - r[2][1]) * 100:.2f},"
                                       f"{(r[1][2] - r[2][2]) * 100:.2f},{np.linalg.norm(eo) * 100:.2f}")
                narrow = np.array([r[5] for r in hold_rows]) < 5.0
                R["holdout"][base][f"split{split}"]["raw_rays_over_5deg"] = stats_cm(err[~narrow])
                pooled[base].append(err)
                pooled_wide[base].append(err[~narrow])
                pooled_off[base].append(err - off)
                log(f"  split {split} ({'even' if split == 0 else 'odd'} blocks calibrate) {base}: "
                    f"{s_raw['epochs']} epochs, median {s_raw['median_cm']:.1f} rms {s_raw['rms_cm']:.1f} "
                    f"p95 {s_raw['p95_cm']:.1f} cm; offset {np.round(off * 100, 1)} cm removed: "
                    f"median {s_off['median_cm']:.1f} rms {s_off['rms_cm']:.1f} p95 {s_off['p95_cm']:.1f} cm")
        for base in ("A", "B"):
            R["holdout"][base]["pooled"] = {"raw": stats_cm(np.vstack(pooled[base])),
                                            "raw_rays_over_5deg": stats_cm(np.vstack(pooled_wide[base])),
                                            "offset_removed": stats_cm(np.vstack(pooled_off[base]))}
        results["datasets"][name] = R
        alignment_json["datasets"][name] = {
            c: {"device": v["device"], "calibration": v["calibration_used"], "fps_nominal": v["fps_nominal"],
                "t0_s": v["t0_s"], "t0_sigma_s": v["t0_sigma_hessian_s"], "t0_utc": utc_str(v["t0_s"], True),
                "s": v["s"], "s_sigma": v["s_sigma"], "residual_rms_px": v["residual_rms_px"]}
            for c, v in R["cameras"].items()}
        export(ds, args.out, origin, align)

    with open(os.path.join(args.out, "results.json"), "w") as fh:
        json.dump(results, fh, indent=1)
    with open(os.path.join(args.out, "holdout_epochs.csv"), "w") as fh:
        fh.write("\n".join(epoch_lines) + "\n")
    with open(os.path.join(args.out, "alignment.json"), "w") as fh:
        json.dump(alignment_json, fh, indent=1)

    log("\nHold-out 3-D error vs RTK (pooled over both splits; every epoch held out once)")
    log(f"{'dataset':9} {'baseline':34} {'epochs':>6} {'median':>7} {'rms':>7} {'p95':>7}  cm | offset removed: median rms p95")
    names = {"A": "A per-camera PnP self-calibration", "B": "B published K,d + PnP pose"}
    for name, R in results["datasets"].items():
        for base in ("A", "B"):
            s, o = R["holdout"][base]["pooled"]["raw"], R["holdout"][base]["pooled"]["offset_removed"]
            log(f"{name:9} {names[base]:34} {s['epochs']:6d} {s['median_cm']:7.1f} {s['rms_cm']:7.1f} {s['p95_cm']:7.1f}"
                f"     | {o['median_cm']:5.1f} {o['rms_cm']:5.1f} {o['p95_cm']:5.1f}")
    log("\nAlignment (global, all labelled frames, model A)")
    for name, R in results["datasets"].items():
        for c, v in R["cameras"].items():
            log(f"{name:9} {c} {v['device']:17} t0 {v['t0_s']:9.4f} s ± {v['t0_sigma_hessian_s'] * 1e3:.2f} ms  "
                f"s-1 {(v['s'] - 1) * 1e6:+7.1f} ± {v['s_sigma'] * 1e6:.1f} ppm  rms {v['residual_rms_px']:.2f} px  "
                f"VFR {v['variable_frame_rate_flag']}")


if __name__ == "__main__":
    main()

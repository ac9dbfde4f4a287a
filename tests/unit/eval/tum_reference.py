#!/usr/bin/python3
"""An independent reference for df_eval's trajectory metrics, written from the definitions of the
TUM RGB-D benchmark (Sturm et al., IROS 2012, and the behaviour of its evaluate_ate.py /
evaluate_rpe.py), with numpy only.

It deliberately computes things differently from the C++ code where it can:
  - the ATE alignment uses Horn's closed-form *quaternion* method (the eigenvector of Horn's
    4x4 matrix N), not an SVD;
  - association uses a dense difference matrix and numpy's lexsort;
  - rotation angles come from atan2 of the skew part and the trace.

Usage: tum_reference.py GT EST [--max-dt 0.02] [--offset 0] [--delta 1] [--form tum|paper]
Prints JSON: {"ate": {...}, "rpe_s": {...}, "rpe_f": {...}} with the keys df_eval --json uses.
"""
import argparse
import json
import sys

import numpy as np


def read_trajectory(path):
    """TUM file -> (sorted stamps (n,), 4x4 poses (n, 4, 4)). A repeated stamp keeps the last line."""
    poses = {}
    with open(path) as f:
        for number, line in enumerate(f, 1):
            line = line.replace(",", " ").replace("\t", " ").strip()
            if not line or line.startswith("#"):
                continue
            v = [float(x) for x in line.split()[:8]]
            if len(v) < 8:
                sys.exit("%s:%d: expected 8 numbers" % (path, number))
            t, (tx, ty, tz, qx, qy, qz, qw) = v[0], v[1:8]
            q = np.array([qw, qx, qy, qz])
            q /= np.linalg.norm(q)
            T = np.eye(4)
            T[:3, :3] = quaternion_to_matrix(q)
            T[:3, 3] = (tx, ty, tz)
            poses[t] = T
    stamps = np.array(sorted(poses))
    return stamps, np.array([poses[s] for s in stamps])


def quaternion_to_matrix(q):
    w, x, y, z = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])


def associate(gt_stamps, est_stamps, offset, max_dt):
    """All pairs with |t_gt - (t_est + offset)| < max_dt, taken by increasing difference (then gt
    stamp, then est stamp), each stamp once; returned sorted by gt stamp as index pairs."""
    diff = np.abs(gt_stamps[:, None] - (est_stamps[None, :] + offset))
    gi, ei = np.nonzero(diff < max_dt)
    d = diff[gi, ei]
    order = np.lexsort((est_stamps[ei], gt_stamps[gi], d))  # last key is the primary one
    used_g, used_e, pairs = set(), set(), []
    for k in order:
        if gi[k] in used_g or ei[k] in used_e:
            continue
        used_g.add(gi[k])
        used_e.add(ei[k])
        pairs.append((gi[k], ei[k]))
    return sorted(pairs)


def horn_quaternion(gt, est):
    """R, t minimising sum |gt_i - (R est_i + t)|^2 by Horn (1987): the unit quaternion is the
    eigenvector of the largest eigenvalue of N built from the cross-covariance."""
    mg, me = gt.mean(axis=0), est.mean(axis=0)
    S = (est - me).T @ (gt - mg)  # S[a, b] = sum est_a gt_b
    (sxx, sxy, sxz), (syx, syy, syz), (szx, szy, szz) = S
    N = np.array([
        [sxx + syy + szz, syz - szy, szx - sxz, sxy - syx],
        [syz - szy, sxx - syy - szz, sxy + syx, szx + sxz],
        [szx - sxz, sxy + syx, -sxx + syy - szz, syz + szy],
        [sxy - syx, szx + sxz, syz + szy, -sxx - syy + szz],
    ])
    values, vectors = np.linalg.eigh(N)
    R = quaternion_to_matrix(vectors[:, np.argmax(values)])
    return R, mg - R @ me


def stats(e):
    e = np.asarray(e, dtype=float)
    return {"count": int(e.size), "rmse": float(np.sqrt(np.mean(e * e))), "mean": float(np.mean(e)),
            "median": float(np.median(e)), "std": float(np.std(e)), "min": float(np.min(e)),
            "max": float(np.max(e))}


def ate(gt_stamps, gt, est_stamps, est, offset, max_dt):
    pairs = associate(gt_stamps, est_stamps, offset, max_dt)
    if len(pairs) < 2:
        sys.exit("fewer than two associated pairs")
    g = np.array([gt[i][:3, 3] for i, _ in pairs])
    e = np.array([est[j][:3, 3] for _, j in pairs])
    R, t = horn_quaternion(g, e)
    errors = np.linalg.norm(e @ R.T + t - g, axis=1)
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, t
    return {"translation_m": stats(errors), "pairs": len(pairs),
            "alignment_gt_T_est": {"matrix": T.tolist()}}


def closest(sorted_values, t):
    """Index of the closest value; of two equally close ones, the earlier."""
    k = int(np.searchsorted(sorted_values, t, side="left"))
    if k == 0:
        return 0
    if k == len(sorted_values):
        return k - 1
    return k if abs(sorted_values[k] - t) < abs(sorted_values[k - 1] - t) else k - 1


def rotation_angle_deg(R):
    skew = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    return np.degrees(np.arctan2(np.linalg.norm(skew) / 2, (np.trace(R) - 1) / 2))


def rpe(gt_stamps, gt, est_stamps, est, offset, delta, unit, form):
    """Relative errors over a fixed delta as TUM's evaluate_rpe.py --fixed_delta (every pair)."""
    n = len(est_stamps)
    index = est_stamps if unit == "s" else np.arange(n, dtype=float)
    max_gt_dt = 2 * np.median(np.diff(gt_stamps))
    trans, rot = [], []
    for i in range(n):
        j = closest(index, index[i] + delta)
        if j == n - 1:  # TUM leaves out pairs that end at the last pose
            continue
        g0 = closest(gt_stamps, est_stamps[i] + offset)
        g1 = closest(gt_stamps, est_stamps[j] + offset)
        if (abs(gt_stamps[g0] - (est_stamps[i] + offset)) > max_gt_dt or
                abs(gt_stamps[g1] - (est_stamps[j] + offset)) > max_gt_dt):
            continue
        A = np.linalg.solve(est[i], est[j])  # est_i^-1 est_j
        B = np.linalg.solve(gt[g0], gt[g1])  # gt_i^-1 gt_j
        E = A @ np.linalg.inv(B) if form == "tum" else np.linalg.solve(B, A)
        trans.append(np.linalg.norm(E[:3, 3]))
        rot.append(rotation_angle_deg(E[:3, :3]))
    if len(trans) < 2:
        sys.exit("fewer than two RPE pairs")
    return {"translation_m": stats(trans), "rotation_deg": stats(rot), "pairs": len(trans)}


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("gt")
    p.add_argument("est")
    p.add_argument("--max-dt", type=float, default=0.02)
    p.add_argument("--offset", type=float, default=0.0)
    p.add_argument("--delta", type=float, default=1.0)
    p.add_argument("--form", choices=["tum", "paper"], default="tum")
    a = p.parse_args()
    gs, g = read_trajectory(a.gt)
    es, e = read_trajectory(a.est)
    out = {"ate": ate(gs, g, es, e, a.offset, a.max_dt),
           "rpe_s": rpe(gs, g, es, e, a.offset, a.delta, "s", a.form),
           "rpe_f": rpe(gs, g, es, e, a.offset, a.delta, "f", a.form)}
    json.dump(out, sys.stdout, indent=1)
    print()


if __name__ == "__main__":
    main()

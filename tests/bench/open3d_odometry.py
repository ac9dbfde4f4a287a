#!/usr/bin/python3
"""The peer of the SLAM benchmark: Open3D's RGB-D odometry (hybrid term, frame to frame) over a
TUM-layout folder, writing a TUM trajectory and the time per frame.

usage: open3d_odometry.py FOLDER OUT_TRAJECTORY [--fx 585 --fy 585 --cx 320 --cy 240
                          --depth-scale 1000 --depth-trunc 3.0]
Needs Debian's python3-open3d (bash deploy/setup.sh --bench)."""
import argparse
import statistics
import sys
import time

import numpy as np
import open3d as o3d


def read_associations(folder):
    pairs = []
    with open(f"{folder}/associations.txt") as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            t_rgb, rgb, _t_depth, depth = line.split()[:4]
            pairs.append((float(t_rgb), f"{folder}/{rgb}", f"{folder}/{depth}"))
    return pairs


def quaternion(r):
    # Rotation matrix to (qx, qy, qz, qw), the branch with the largest diagonal term.
    m = r
    tr = m[0, 0] + m[1, 1] + m[2, 2]
    if tr > 0:
        s = 2.0 * np.sqrt(tr + 1.0)
        return ((m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s, 0.25 * s)
    i = int(np.argmax([m[0, 0], m[1, 1], m[2, 2]]))
    j, k = (i + 1) % 3, (i + 2) % 3
    s = 2.0 * np.sqrt(1.0 + m[i, i] - m[j, j] - m[k, k])
    q = [0.0, 0.0, 0.0]
    q[i] = 0.25 * s
    q[j] = (m[j, i] + m[i, j]) / s
    q[k] = (m[k, i] + m[i, k]) / s
    return (q[0], q[1], q[2], (m[k, j] - m[j, k]) / s)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("folder")
    p.add_argument("out")
    p.add_argument("--fx", type=float, default=585.0)
    p.add_argument("--fy", type=float, default=585.0)
    p.add_argument("--cx", type=float, default=320.0)
    p.add_argument("--cy", type=float, default=240.0)
    p.add_argument("--depth-scale", type=float, default=1000.0)
    p.add_argument("--depth-trunc", type=float, default=3.0)
    a = p.parse_args()
    intrinsic = o3d.camera.PinholeCameraIntrinsic(640, 480, a.fx, a.fy, a.cx, a.cy)
    option = o3d.pipelines.odometry.OdometryOption()
    jacobian = o3d.pipelines.odometry.RGBDOdometryJacobianFromHybridTerm()
    pose = np.eye(4)
    previous = None
    times, failures = [], 0
    with open(a.out, "w") as out:
        for stamp, rgb_file, depth_file in read_associations(a.folder):
            colour = o3d.io.read_image(rgb_file)
            depth = np.asarray(o3d.io.read_image(depth_file)).copy()
            depth[depth == 65535] = 0  # 7-Scenes marks invalid depth with 65535
            rgbd = o3d.geometry.RGBDImage.create_from_color_and_depth(
                colour, o3d.geometry.Image(depth), depth_scale=a.depth_scale,
                depth_trunc=a.depth_trunc, convert_rgb_to_intensity=True)
            if previous is not None:
                start = time.perf_counter()
                ok, current_T_previous_inv, _ = o3d.pipelines.odometry.compute_rgbd_odometry(
                    rgbd, previous, intrinsic, np.eye(4), jacobian, option)
                times.append(time.perf_counter() - start)
                if ok:
                    # The result maps points of the source (current) into the target (previous).
                    pose = pose @ current_T_previous_inv
                else:
                    failures += 1
            previous = rgbd
            qx, qy, qz, qw = quaternion(pose[:3, :3])
            t = pose[:3, 3]
            out.write(f"{stamp:.6f} {t[0]:.9f} {t[1]:.9f} {t[2]:.9f} {qx:.9f} {qy:.9f} {qz:.9f} {qw:.9f}\n")
    print(f"open3d odometry: {len(times) + 1} frames, {failures} failed, "
          f"median {statistics.median(times) * 1000:.1f} ms, mean {statistics.mean(times) * 1000:.1f} ms per frame")


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""Absolute trajectory error of an MRPT icp-slam run against a per-scan reference trajectory.

Usage: tests/bench/mrpt_ate.py PATH_TXT GT_TXT [--out PER_SCAN_POSES.txt]

PATH_TXT is icp-slam's log_estimated_path.txt (or log_odometry_path.txt): one line
`step x y yaw` per rawlog entry. With a rawlog from carmen2rawlog every scan becomes two entries,
the odometry observation and then the laser scan, so scan k is step 2k+1 and the pose written
there is icp-slam's estimate right after it processed that scan (the ICP-corrected pose when ICP
ran, else the last correction composed with the odometry since). A file with exactly one line per
scan is taken as is.
GT_TXT holds `t x y theta` per scan, in scan order (intel-gt.txt).

ATE = RMSE of the positions after the best rigid 2D alignment (rotation + translation, no scale,
closed form as in Umeyama/Horn) of the estimates onto the reference. Plain python3, no numpy.
Prints `ATE <m> scans <n> max <m>`.
"""
import argparse
import math
import sys


def read_rows(path, ncols):
    rows = []
    with open(path) as f:
        for line in f:
            tok = line.split()
            if not tok or tok[0].startswith(("%", "#")):
                continue
            rows.append([float(v) for v in tok[:ncols]])
    return rows


def align_rmse(est, ref):
    """Best rigid 2D (R, t) minimising sum |R e + t - g|^2; returns (rmse, max, theta, tx, ty)."""
    n = len(est)
    mex = sum(e[0] for e in est) / n
    mey = sum(e[1] for e in est) / n
    mgx = sum(g[0] for g in ref) / n
    mgy = sum(g[1] for g in ref) / n
    sc = ss = 0.0
    for (ex, ey), (gx, gy) in zip(est, ref):
        ex -= mex
        ey -= mey
        gx -= mgx
        gy -= mgy
        sc += ex * gx + ey * gy
        ss += ex * gy - ey * gx
    th = math.atan2(ss, sc)
    c, s = math.cos(th), math.sin(th)
    tx = mgx - (c * mex - s * mey)
    ty = mgy - (s * mex + c * mey)
    se = 0.0
    worst = 0.0
    for (ex, ey), (gx, gy) in zip(est, ref):
        dx = c * ex - s * ey + tx - gx
        dy = s * ex + c * ey + ty - gy
        d2 = dx * dx + dy * dy
        se += d2
        worst = max(worst, d2)
    return math.sqrt(se / n), math.sqrt(worst), th, tx, ty


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("path")
    ap.add_argument("gt")
    ap.add_argument("--out", help="write the per-scan estimates `k x y yaw` here")
    a = ap.parse_args()

    gt = read_rows(a.gt, 4)
    path = read_rows(a.path, 4)
    n = len(gt)
    if len(path) == 2 * n:
        per_scan = [path[2 * k + 1] for k in range(n)]
    elif len(path) == n:
        per_scan = path
    else:
        sys.exit("%s has %d entries; expected %d (scans) or %d (odometry + scan per scan)"
                 % (a.path, len(path), n, 2 * n))
    if a.out:
        with open(a.out, "w") as o:
            for k, p in enumerate(per_scan):
                o.write("%d %.6f %.6f %.6f\n" % (k, p[1], p[2], p[3]))
    rmse, worst, _, _, _ = align_rmse([(p[1], p[2]) for p in per_scan],
                                      [(g[1], g[2]) for g in gt])
    print("ATE %.4f scans %d max %.4f" % (rmse, n, worst))


if __name__ == "__main__":
    main()

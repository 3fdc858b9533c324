#!/usr/bin/env python3
"""Rewrite a CARMEN laser log (.log or .log.gz) so that MRPT 2.5's carmen2rawlog reads it right.

Usage: tests/bench/mrpt_carmen_prep.py IN.log[.gz] OUT.log [--max-range M] [--fov-deg F]
                                      [--time-scale S]

Why: carmen2rawlog (MRPT 2.5.8, Debian 12) has four traps for logs such as the Intel Research Lab
one, each of which on its own wrecks icp-slam:
  1. Without a `PARAM laser_front_laser_resolution` line it assumes 0.5 deg between beams, so a
     180-beam 1-deg scan is squeezed into a 90-deg fan. We write that PARAM so the n beams span
     (n-1) * step (MRPT spreads n beams over its aperture end to end), and we turn the sensor by
     -step/2 so beam i lies at -FOV/2 + i * step (-90 .. +89 deg for the Intel log), exactly as
     the log means.
  2. It reads the time stamp field as `1e-6 * t` microseconds, so every observation gets the same
     time stamp; CRobot2DPoseEstimator then stops applying odometry after the first ICP fix (it
     only adds odometry that is newer than the last fix). We write t * S in the field (S = 1e12
     by default) so that MRPT's parse yields t seconds again, and we make the times strictly
     increasing (the Intel log has four scans stamped earlier than the one before: those get the
     previous time + 1 ms).
  3. The robot (odometry) pose comes from the odometry pose of the FLASER line; the sensor pose on
     the robot is "laser pose - odometry pose". We keep the odometry pose and rewrite the laser
     pose field as odometry (+) (0, 0, -step/2), so the sensor sits at the robot origin turned by
     -step/2 (trap 1) whatever the first pose field held.
  4. A reading is invalid only when range >= robot_front_laser_max (default 81). We write the
     maximum range (default: the largest reading in the log, i.e. the sensor's "no return"
     value) so that max-range readings are dropped and every real return is kept.
ODOM, NEFF, PARAM and every other line are dropped: the odometry comes only from the FLASER lines
(the ODOM lines of these logs are not raw odometry).
Prints one line to stderr: scans written, max range, step, time stamps fixed.
"""
import argparse
import gzip
import math
import sys


def open_text(path):
    if path.endswith(".gz"):
        return gzip.open(path, "rt")
    return open(path, "r")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("inp")
    ap.add_argument("out")
    ap.add_argument("--max-range", type=float, default=0.0,
                    help="readings >= this are 'no return' (default: largest reading in the log)")
    ap.add_argument("--fov-deg", type=float, default=180.0,
                    help="field of view covered by the n beams, n*step (default 180)")
    ap.add_argument("--time-scale", type=float, default=1e12,
                    help="factor written into the time field (1e12 undoes MRPT 2.5's 1e-6 us parse)")
    a = ap.parse_args()

    scans = []  # (ranges[str], odom (x, y, th), t)
    with open_text(a.inp) as f:
        for line in f:
            tok = line.split()
            if not tok or tok[0] != "FLASER":
                continue
            n = int(tok[1])
            ranges = tok[2:2 + n]
            rest = tok[2 + n:]
            ox, oy, oth = float(rest[3]), float(rest[4]), float(rest[5])
            t = float(rest[6])
            scans.append((ranges, (ox, oy, oth), t))
    if not scans:
        sys.exit("no FLASER line in " + a.inp)

    max_range = a.max_range
    if max_range <= 0:
        max_range = max(float(r) for s in scans for r in s[0])
    n = len(scans[0][0])
    step_deg = a.fov_deg / n
    # MRPT: aperture = resolution * n, beams spaced aperture / (n - 1); we want spacing = step.
    resolution_deg = step_deg * (n - 1) / n
    yaw_off = -math.radians(step_deg) / 2.0

    fixed = 0
    last_t = None
    with open(a.out, "w") as o:
        o.write("PARAM robot_front_laser_max %.6f\n" % max_range)
        o.write("PARAM laser_front_laser_resolution %.12f\n" % resolution_deg)
        for ranges, (ox, oy, oth), t in scans:
            if len(ranges) != n:
                sys.exit("scans with different beam counts are not supported")
            if last_t is not None and t <= last_t:
                t = last_t + 1e-3
                fixed += 1
            last_t = t
            lx = ox
            ly = oy
            lth = oth + yaw_off
            o.write("FLASER %d %s %.6f %.6f %.9f %.6f %.6f %.9f %.0f nohost %.6f\n" % (
                n, " ".join(ranges), lx, ly, lth, ox, oy, oth, t * a.time_scale, t))
    print("prep: %d scans, max range %.3f m, step %.4f deg, %d time stamps fixed"
          % (len(scans), max_range, step_deg, fixed), file=sys.stderr)


if __name__ == "__main__":
    main()

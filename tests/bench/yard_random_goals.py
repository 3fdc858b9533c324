#!/usr/bin/env python3
"""Random goals for a tricycle in the yard, many more than the API test's ten, against a fresh
mobotd: each goal at least 3 m from every obstacle of the active map and more than 5 m from where
the robot stands, one after the other from wherever the last one ended. Prints each goal's end,
and every goal refused at once (422: no path from where the robot stopped).

    tests/bench/yard_random_goals.py tricycle_t2 40 12     # config, goals, seed
"""
import json
import math
import random
import re
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request

CLEARANCE_M = 3.0
MIN_TRAVEL_M = 5.0


def main():
    config, goals, seed = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    server = subprocess.Popen(
        ["build/server/mobotd", "--config", f"deploy/config/{config}.yaml", "--port", "0",
         "--data-dir", tempfile.mkdtemp(), "--token", "T", "--time-scale", "10",
         "--log-level", "warn"],
        stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    port = None
    for line in server.stdout:
        found = re.search(r"listening on https?://[^:]+:(\d+)", line)
        if found:
            port = int(found.group(1))
            break

    def call(method, path, body=None, raw=False):
        request = urllib.request.Request(
            f"http://127.0.0.1:{port}{path}", method=method,
            data=None if body is None else json.dumps(body).encode(),
            headers={"Authorization": "Bearer T", "Content-Type": "application/json"})
        try:
            with urllib.request.urlopen(request) as reply:
                data = reply.read()
                return reply.status, data if raw else json.loads(data or b"null")
        except urllib.error.HTTPError as error:
            return error.code, json.loads(error.read() or b"null")

    try:
        active = [m for m in call("GET", "/api/v1/maps")[1] if m.get("active")][0]
        _, pgm = call("GET", f"/api/v1/maps/{active['id']}/map.pgm", raw=True)
        header = pgm.split(b"\n", 3)
        width, height = map(int, header[1].split())
        pixels = header[3]
        res, ox, oy = active["resolution"], active["origin"]["x"], active["origin"]["y"]
        # Occupied cells' centres (row 0 of the image is the top of the map).
        occupied = [(ox + (c % width + 0.5) * res, oy + (height - 1 - c // width + 0.5) * res)
                    for c in range(width * height) if pixels[c] < 100]

        def clear(x, y):
            return all(abs(px - x) > CLEARANCE_M or abs(py - y) > CLEARANCE_M
                       or math.hypot(px - x, py - y) >= CLEARANCE_M for px, py in occupied)

        rng = random.Random(seed)
        refused = 0
        for i in range(goals):
            here = call("GET", "/api/v1/sim/truth")[1]["pose"]
            while True:
                x, y = rng.uniform(ox, ox + width * res), rng.uniform(oy, oy + height * res)
                if math.hypot(x - here["x"], y - here["y"]) > MIN_TRAVEL_M and clear(x, y):
                    break
            status, goal = call("POST", "/api/v1/goals", {"x": x, "y": y})
            if status != 201:
                refused += 1
                code = (goal or {}).get("error", {}).get("code")
                print(f"{i} REFUSED {status} {code} from ({here['x']:.2f}, {here['y']:.2f}, "
                      f"{here['theta']:.2f}) to ({x:.2f}, {y:.2f})")
                continue
            started = time.time()
            while time.time() - started < 60:
                goal = call("GET", f"/api/v1/goals/{goal['id']}")[1]
                if goal.get("status") in ("succeeded", "failed", "cancelled"):
                    break
                time.sleep(0.1)
            print(f"{i} {goal.get('status')} {goal.get('reason', '')} ({x:.1f}, {y:.1f})")
        print(f"{goals} goals, {refused} refused")
    finally:
        server.terminate()
        server.wait()


if __name__ == "__main__":
    main()

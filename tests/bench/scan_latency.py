#!/usr/bin/env python3
"""Latency of a lidar scan from the emulated YDLIDAR G4's serial line to mobotd's WebSocket.

Usage: tests/bench/scan_latency.py [--build-dir build] [--emulator PATH] [--mobotd PATH]
                                   [--seconds 30] [--warmup 2] [--keep DIR]

Starts `mobot-emulate dashgo --trace-scans FILE` (one line per completed lidar turn: the
CLOCK_REALTIME microsecond at which the last byte of the zero packet that completes it was written
to the pty, the moment the host's assembler can close the turn), then
`mobotd --backend hardware` on the emulated devices, subscribes a WebSocket client to the `scan`
topic in binary and stamps every scan frame with CLOCK_REALTIME as it is received. Each frame
belongs to the newest turn completed before it arrived: latency = receipt - that trace time.

The frame's own wall_us (stamped by mobotd when the control tick publishes it) splits the latency
into serial line -> publication and publication -> receipt (the rest of the tick, the hub's flush,
loopback, this client). The pose topic (JSON, every tick) places the ticks in wall time: robot time
t advances by one period per tick and the ticks run on absolute deadlines, so a tick starts at
T0 + t, and T0 is taken as the smallest wall_us - t over the pose frames (the earliest any tick
published; it overestimates the start by a light tick's duration, about 0.2 ms). The scan frame's
t is the tick that polled the laser, which splits serial line -> publication into the wait for
that tick (the driver thread's read and parse, then the wait for the 50 Hz poll) and the tick's
stages up to the publication.

Python 3 standard library only; the WebSocket client is the minimum of RFC 6455 this needs.
Prints count, p50, p90, p99 and max in ms, and the command line that reproduces the run.
"""
import argparse
import base64
import bisect
import hashlib
import json
import os
import re
import secrets
import shlex
import shutil
import signal
import socket
import struct
import subprocess
import sys
import tempfile
import time
import urllib.request

WS_GUID = "258EAFA5-E914-47DA-95CA-C5AB0DC85B11"
OP_CONTINUATION, OP_TEXT, OP_BINARY, OP_CLOSE, OP_PING, OP_PONG = 0x0, 0x1, 0x2, 0x8, 0x9, 0xA
FRAME_MAGIC = b"MBT1"
FRAME_HEADER = struct.Struct("<4sHHQdq")  # magic, topic id, header_bytes, seq, t, wall_us
TOPIC_SCAN = 1
LISTENING = re.compile(r"mobotd listening on http://([^\s:/]+):(\d+)")


def realtime_us():
    return time.clock_gettime_ns(time.CLOCK_REALTIME) // 1000


class WebSocket:
    """A client end of RFC 6455: the upgrade, masked frames out, unmasked frames in."""

    def __init__(self, host, port, path):
        self.sock = socket.create_connection((host, port), timeout=5.0)
        self.sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        key = base64.b64encode(secrets.token_bytes(16)).decode()
        request = (f"GET {path} HTTP/1.1\r\nHost: {host}:{port}\r\nUpgrade: websocket\r\n"
                   f"Connection: Upgrade\r\nSec-WebSocket-Key: {key}\r\n"
                   "Sec-WebSocket-Version: 13\r\n\r\n")
        self.sock.sendall(request.encode())
        self.buffer = b""
        while b"\r\n\r\n" not in self.buffer:
            chunk = self.sock.recv(4096)
            if not chunk:
                raise RuntimeError("the server closed the connection during the upgrade")
            self.buffer += chunk
        head, self.buffer = self.buffer.split(b"\r\n\r\n", 1)
        lines = head.decode("latin-1").split("\r\n")
        if " 101 " not in lines[0] + " ":
            raise RuntimeError(f"upgrade refused: {lines[0]}")
        headers = {k.strip().lower(): v.strip() for k, v in
                   (line.split(":", 1) for line in lines[1:] if ":" in line)}
        accept = base64.b64encode(hashlib.sha1((key + WS_GUID).encode()).digest()).decode()
        if headers.get("sec-websocket-accept") != accept:
            raise RuntimeError("bad Sec-WebSocket-Accept")
        self.fragments = []
        self.fragment_opcode = None

    def send(self, opcode, payload):
        # Every client frame is masked (RFC 6455 5.3); the server must drop unmasked ones.
        mask = secrets.token_bytes(4)
        size = len(payload)
        if size < 126:
            head = struct.pack("!BB", 0x80 | opcode, 0x80 | size)
        elif size < 1 << 16:
            head = struct.pack("!BBH", 0x80 | opcode, 0x80 | 126, size)
        else:
            head = struct.pack("!BBQ", 0x80 | opcode, 0x80 | 127, size)
        masked = bytes(b ^ mask[i % 4] for i, b in enumerate(payload))
        self.sock.sendall(head + mask + masked)

    def send_text(self, text):
        self.send(OP_TEXT, text.encode())

    def _parse_one(self):
        """One whole frame from the buffer as (fin, opcode, payload), or None if incomplete."""
        buf = self.buffer
        if len(buf) < 2:
            return None
        fin, opcode = buf[0] & 0x80, buf[0] & 0x0F
        masked, size = buf[1] & 0x80, buf[1] & 0x7F
        at = 2
        if size == 126:
            if len(buf) < 4:
                return None
            size = struct.unpack_from("!H", buf, 2)[0]
            at = 4
        elif size == 127:
            if len(buf) < 10:
                return None
            size = struct.unpack_from("!Q", buf, 2)[0]
            at = 10
        mask = b""
        if masked:
            mask = buf[at:at + 4]
            at += 4
        if len(buf) < at + size:
            return None
        payload = buf[at:at + size]
        if masked:
            payload = bytes(b ^ mask[i % 4] for i, b in enumerate(payload))
        self.buffer = buf[at + size:]
        return bool(fin), opcode, payload

    def receive(self, timeout_s):
        """The messages completed by one read: [(opcode, payload)], [] on a time-out."""
        self.sock.settimeout(timeout_s)
        try:
            chunk = self.sock.recv(1 << 16)
        except socket.timeout:
            return []
        if not chunk:
            raise ConnectionError("the server closed the connection")
        self.buffer += chunk
        messages = []
        while (frame := self._parse_one()) is not None:
            fin, opcode, payload = frame
            if opcode == OP_PING:
                self.send(OP_PONG, payload)
                continue
            if opcode == OP_CLOSE:
                raise ConnectionError("the server sent close")
            if opcode == OP_PONG:
                continue
            if opcode != OP_CONTINUATION:
                self.fragment_opcode, self.fragments = opcode, []
            self.fragments.append(payload)
            if fin:
                messages.append((self.fragment_opcode, b"".join(self.fragments)))
                self.fragments = []
        return messages

    def close(self):
        try:
            self.send(OP_CLOSE, struct.pack("!H", 1000))
        except OSError:
            pass
        self.sock.close()


def wait_for_line(path, pattern, process, timeout_s):
    """The first match of `pattern` in the file `path` that `process` writes."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        with open(path, errors="replace") as f:
            match = pattern.search(f.read())
        if match:
            return match
        if process.poll() is not None:
            raise RuntimeError(f"{process.args[0]} exited ({process.returncode}); see {path}")
        time.sleep(0.05)
    raise RuntimeError(f"no '{pattern.pattern}' from {process.args[0]} in {timeout_s} s")


def percentile(sorted_values, fraction):
    """Nearest-rank percentile of a sorted list."""
    rank = max(1, -(-len(sorted_values) * fraction // 1))
    return sorted_values[int(rank) - 1]


def summary_row(name, values_ms):
    values = sorted(values_ms)
    return (f"| {name} | {len(values)} | {percentile(values, 0.5):.2f} | "
            f"{percentile(values, 0.9):.2f} | {percentile(values, 0.99):.2f} | "
            f"{values[0]:.2f} | {values[-1]:.2f} |")


def control_loop_metrics(host, port, token):
    """mobotd's own figures of its control loop, from /metrics: name -> value."""
    request = urllib.request.Request(f"http://{host}:{port}/metrics",
                                     headers={"Authorization": f"Bearer {token}"})
    try:
        with urllib.request.urlopen(request, timeout=5) as response:
            text = response.read().decode()
    except OSError as error:
        return {"error": str(error)}
    values = {}
    for line in text.splitlines():
        if line.startswith("mobot_control_") and " " in line:
            name, value = line.rsplit(" ", 1)
            values[name] = float(value)
    return values


def stop(process, how):
    if process is None or process.poll() is not None:
        return
    try:
        how(process)
        process.wait(timeout=5)
    except (subprocess.TimeoutExpired, OSError, ValueError):
        process.kill()
        process.wait()


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--build-dir", default="build", help="where mobotd and mobot-emulate are")
    parser.add_argument("--emulator", help="mobot-emulate with --trace-scans "
                        "(default BUILD/tools/mobot-emulate)")
    parser.add_argument("--mobotd", help="default BUILD/server/mobotd")
    parser.add_argument("--seconds", type=float, default=30.0, help="measured window")
    parser.add_argument("--warmup", type=float, default=2.0,
                        help="seconds of frames dropped after subscribing (the lidar spins up)")
    parser.add_argument("--keep", help="keep the emulator's dir, logs and trace here")
    args = parser.parse_args()
    emulator = args.emulator or os.path.join(args.build_dir, "tools", "mobot-emulate")
    mobotd = args.mobotd or os.path.join(args.build_dir, "server", "mobotd")

    work = args.keep or tempfile.mkdtemp(prefix="scan_latency.")
    os.makedirs(work, exist_ok=True)
    device_dir = os.path.join(work, "dashgo")
    data_dir = os.path.join(work, "data")
    trace_path = os.path.join(work, "scan_trace.txt")
    emulator_log = os.path.join(work, "emulate.log")
    mobotd_log = os.path.join(work, "mobotd.log")
    if os.path.exists(trace_path):
        os.remove(trace_path)
    token = "latency-" + secrets.token_hex(8)

    emu = server = ws = None
    frames = []  # (receipt us, publication wall_us, seq, robot time t of the tick)
    poses = []  # (robot time t, publication wall_us), one per tick
    metrics = {}
    try:
        # stdin stays open: the emulator quits at the end of its input.
        with open(emulator_log, "w") as log:
            emu = subprocess.Popen([emulator, "dashgo", "--dir", device_dir, "--trace-scans",
                                    trace_path], stdin=subprocess.PIPE, stdout=log,
                                   stderr=subprocess.STDOUT)
        wait_for_line(emulator_log, re.compile(r"^ready$", re.M), emu, 10.0)
        with open(mobotd_log, "w") as log:
            server = subprocess.Popen([mobotd, "--backend", "hardware", "--config",
                                       os.path.join(device_dir, "mobotd.yaml"), "--port", "0",
                                       "--data-dir", data_dir, "--token", token,
                                       "--time-scale", "1"], stdout=log, stderr=subprocess.STDOUT)
        listening = wait_for_line(mobotd_log, LISTENING, server, 15.0)
        host, port = listening.group(1), int(listening.group(2))

        ws = WebSocket(host, port, f"/api/v1/stream?token={token}")
        ws.send_text(json.dumps({"op": "subscribe", "topics": ["scan", "pose"],
                                 "encoding": "binary"}))
        start_s = time.monotonic()
        measure_from_s = start_s + args.warmup
        end_s = measure_from_s + args.seconds
        while (now_s := time.monotonic()) < end_s:
            messages = ws.receive(min(0.5, end_s - now_s))
            # One stamp per read: every frame it completed was in the socket by then.
            received_us = realtime_us()
            for opcode, payload in messages:
                if now_s < measure_from_s:
                    continue
                if opcode == OP_TEXT:
                    message = json.loads(payload)
                    if message.get("topic") == "pose":
                        poses.append((message["t"], message["wall_us"]))
                    continue
                if opcode != OP_BINARY or len(payload) < FRAME_HEADER.size:
                    continue
                magic, topic, _, seq, t_s, wall_us = FRAME_HEADER.unpack_from(payload)
                if magic == FRAME_MAGIC and topic == TOPIC_SCAN:
                    frames.append((received_us, wall_us, seq, t_s))
        metrics = control_loop_metrics(host, port, token)
    finally:
        if ws is not None:
            ws.close()
        stop(server, lambda p: p.send_signal(signal.SIGINT))
        stop(emu, lambda p: p.communicate(b"quit\n", timeout=5))

    with open(trace_path) as f:
        trace_us = sorted(int(line) for line in f if line.strip())
    # Wall time of robot time 0; see the module's description.
    t0_us = min((wall_us - round(t_s * 1e6) for t_s, wall_us in poses), default=None)
    total, publish, deliver, wait, stages = [], [], [], [], []
    unmatched = 0
    matched_turns = set()
    for received_us, wall_us, _, t_s in frames:
        # The frame carries the newest turn whose last packet was out before it arrived.
        i = bisect.bisect_right(trace_us, received_us) - 1
        if i < 0:
            unmatched += 1
            continue
        matched_turns.add(i)
        total.append((received_us - trace_us[i]) / 1000.0)
        publish.append((wall_us - trace_us[i]) / 1000.0)
        deliver.append((received_us - wall_us) / 1000.0)
        if t0_us is not None:
            tick_start_us = t0_us + round(t_s * 1e6)
            wait.append((tick_start_us - trace_us[i]) / 1000.0)
            stages.append((wall_us - tick_start_us) / 1000.0)

    in_window = [t for t in trace_us if frames and frames[0][0] - 200000 <= t <= frames[-1][0]]
    seqs = [frame[2] for frame in frames]
    lost = sum(b - a - 1 for a, b in zip(seqs, seqs[1:]) if b > a + 1)
    print(f"scan frames {len(frames)} in {args.seconds:.0f} s, turns traced in that span "
          f"{len(in_window)}, frames matched to a distinct turn {len(matched_turns)}, "
          f"seq gaps {lost}, unmatched {unmatched}")
    if total:
        print("| latency (ms) | n | p50 | p90 | p99 | min | max |")
        print("|---|---|---|---|---|---|---|")
        print(summary_row("last byte on the pty -> frame received", total))
        print(summary_row("last byte on the pty -> published (wall_us)", publish))
        print(summary_row("published -> frame received", deliver))
        if wait:
            print(summary_row("last byte on the pty -> start of the tick that polls it", wait))
            print(summary_row("start of that tick -> published", stages))
    if metrics:
        print("mobotd control loop: " + ", ".join(
            f"{name.removeprefix('mobot_control_')} {value:.6g}" for name, value in metrics.items()
            if "tick" in name or name == "error"))
    command = [sys.argv[0], "--build-dir", args.build_dir, "--seconds", f"{args.seconds:g}",
               "--warmup", f"{args.warmup:g}"]
    if args.emulator:
        command += ["--emulator", args.emulator]
    if args.mobotd:
        command += ["--mobotd", args.mobotd]
    print("reproduce: " + shlex.join(command))
    if not args.keep:
        shutil.rmtree(work, ignore_errors=True)
    return 0 if total else 1


if __name__ == "__main__":
    sys.exit(main())

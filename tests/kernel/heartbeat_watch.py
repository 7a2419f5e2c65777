#!/usr/bin/env python3
"""Power-cut test, host side of one boot: read rig-sim's heartbeat from the VM's second serial
port (a Unix socket QEMU serves), cut the power (SIGKILL to QEMU) on SIGUSR1, and tell the
guest's CLOCK_MONOTONIC at the cut.

Each heartbeat line is "<now_us> <age_us>" (sim/server/heartbeat_writer.hpp): when rig-sim
wrote it and how long before that rigd's last DAQ read arrived, on the guest's clock [us]. The
write reaches this process through a chain without queues (guest tty -> emulated UART -> QEMU's
vCPU thread writes the socket), so arrival (host clock) - now_us = the clocks' offset + a lag
>= 0; the smallest value over the last WINDOW_S before the cut is the offset (plus the fastest
lag, tens of microseconds), and the guest's clock at the cut = host clock just after kill()
returned - that offset. Under TCG the guest's clock runs at the host's rate (QEMU_CLOCK_VIRTUAL);
the offset's change over the boot is reported as drift_us.

usage: heartbeat_watch.py SOCKET QEMU_PID OUT
OUT: "<cut_us> <last_read_us> <last_line_us> <lines> <window_lines> <drift_us> <dropped>" on the
guest's clock [us], or "none <lines>" when QEMU ended without a cut (or no heartbeat came).
"""
import os
import signal
import socket
import sys
import time

WINDOW_S = 2.0   # offset from the lines of the last 2 s before the cut [s]
CONNECT_S = 30.0  # QEMU creates the socket at start-up [s]


def connect(path, qemu_pid):
    deadline = time.monotonic() + CONNECT_S
    while True:
        s = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        try:
            s.connect(path)
            return s
        except OSError:
            s.close()
            if time.monotonic() > deadline or not alive(qemu_pid):
                return None
            time.sleep(0.02)


def alive(pid):
    try:
        os.kill(pid, 0)
        return True
    except OSError:
        return False


class Watch:
    def __init__(self, qemu_pid):
        self.qemu_pid = qemu_pid
        self.cut_ns = None        # host CLOCK_MONOTONIC just after kill() returned [ns]
        self.lines = []           # (arrival_ns, now_us, age_us)
        self.dropped = 0
        self.partial = b""

    def cut(self, _signum, _frame):
        if self.cut_ns is None:
            os.kill(self.qemu_pid, signal.SIGKILL)
            self.cut_ns = time.monotonic_ns()

    def take(self, data, arrival_ns):
        *complete, self.partial = (self.partial + data).split(b"\n")
        for raw in complete:
            fields = raw.strip(b"\r").split()
            try:
                now_us, age_us = int(fields[0]), int(fields[1])
            except (IndexError, ValueError):
                self.dropped += 1   # torn by a dropped write or the cut
                continue
            if len(fields) == 2:
                self.lines.append((arrival_ns, now_us, age_us))

    def summary(self):
        if self.cut_ns is None or not self.lines:
            return f"none {len(self.lines)}"
        window = [l for l in self.lines if l[0] >= self.cut_ns - WINDOW_S * 1e9] or self.lines[-1:]
        offset_us = min(a / 1000 - now for a, now, _ in window)
        first_offset_us = min(a / 1000 - now for a, now, _ in self.lines[:len(window)])
        cut_us = self.cut_ns / 1000 - offset_us
        last_read_us = max(now - age for _, now, age in self.lines if age >= 0) if any(
            age >= 0 for *_, age in self.lines) else -1
        return (f"{cut_us:.0f} {last_read_us} {self.lines[-1][1]} {len(self.lines)} {len(window)} "
                f"{offset_us - first_offset_us:.0f} {self.dropped}")


def main():
    path, qemu_pid, out = sys.argv[1], int(sys.argv[2]), sys.argv[3]
    watch = Watch(qemu_pid)
    signal.signal(signal.SIGUSR1, watch.cut)
    conn = connect(path, qemu_pid)
    while conn is not None:
        data = conn.recv(4096)   # retried after SIGUSR1's handler ran (PEP 475)
        if not data:
            break                # QEMU is gone: cut, or powered off
        watch.take(data, time.monotonic_ns())
    with open(out, "w") as f:
        f.write(watch.summary() + "\n")


if __name__ == "__main__":
    main()

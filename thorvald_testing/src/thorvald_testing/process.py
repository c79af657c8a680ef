"""Running nodes as processes and collecting what they print."""
import os
import pty
import select
import signal
import subprocess
import threading
import time

STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGQUIT, signal.SIGHUP)


def restore_default_signals():
    """For `preexec_fn`: the child gets the default handling of the stop signals back. A test suite started in the
    background (`&` in a script), under nohup or by a CI runner may ignore SIGINT, and a child inherits that: a test
    that stops a child with SIGINT would then depend on how the suite was started."""
    for sig in STOP_SIGNALS:
        signal.signal(sig, signal.SIG_DFL)
    signal.pthread_sigmask(signal.SIG_SETMASK, [])


def run_until_line(command, wanted=None, deadline_s=30.0, env=None, stop_signal=signal.SIGINT, stop_wait_s=10.0):
    """Runs `command` (a list), its stdout and stderr merged. Without `wanted`, waits for it to exit; with it, stops
    it with `stop_signal` once a line contains `wanted`. At the deadline a running command is stopped the same way
    (and killed if it does not exit within `stop_wait_s`).

    Returns (exit code, output): the exit code is None when the command had to be stopped because `wanted` was
    never seen (deadline) or did not exit after the signal."""
    proc = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            env=dict(os.environ, ROSCONSOLE_STDOUT_LINE_BUFFERED="1", **(env or {})),
                            preexec_fn=restore_default_signals)
    lines = []
    seen = False
    ended = False  # its output closed: it is exiting by itself
    end = time.monotonic() + deadline_s
    try:
        while time.monotonic() < end:
            ready, _, _ = select.select([proc.stdout], [], [], 0.5)
            if not ready:
                continue
            line = proc.stdout.readline()
            if not line:
                ended = True
                break
            lines.append(line)
            if wanted is not None and wanted in line:
                seen = True
                break
    finally:
        stopped = not ended and proc.poll() is None
        if stopped:
            proc.send_signal(stop_signal)
        try:
            code = proc.wait(timeout=stop_wait_s)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
            code = None
        if stopped and not seen:
            code = None
        proc.stdout.close()
    return code, "".join(lines)


class PtyProcess:
    """A process whose stdin, stdout and stderr are one pseudo-terminal, in a session of its own (so a terminal
    signal sent to it reaches it alone). What it prints is collected by a background thread."""

    def __init__(self, argv, env=None, stderr_to_pty=True, keep_slave=False):
        """`keep_slave`: keep the terminal's slave end open here too, for `canonical()`."""
        self.master_fd, slave_fd = pty.openpty()
        self.proc = subprocess.Popen(argv, stdin=slave_fd, stdout=slave_fd,
                                     stderr=slave_fd if stderr_to_pty else subprocess.DEVNULL,
                                     env=dict(os.environ, **(env or {})), start_new_session=True,
                                     preexec_fn=restore_default_signals)
        self.slave_fd = slave_fd if keep_slave else None
        if not keep_slave:
            os.close(slave_fd)
        self._output = b""
        self._lock = threading.Lock()
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self):
        while True:
            try:
                data = os.read(self.master_fd, 4096)
            except OSError:
                return
            if not data:
                return
            with self._lock:
                self._output += data

    def text(self):
        """Everything printed so far."""
        with self._lock:
            return self._output.decode(errors="replace")

    def write(self, data):
        """Types `data` (bytes) on the terminal."""
        os.write(self.master_fd, data)

    def stop(self, sig, timeout=10.0):
        """Sends `sig`; returns (exit code, seconds to exit), or (None, None) if it still runs after `timeout`."""
        sent = time.monotonic()
        self.proc.send_signal(sig)
        try:
            code = self.proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            return None, None
        return code, time.monotonic() - sent

    def canonical(self):
        """Whether the terminal is in canonical (line) mode, as a node leaves it; needs `keep_slave`."""
        import termios

        return bool(termios.tcgetattr(self.slave_fd)[3] & termios.ICANON)

    def close(self):
        """Kills the process if it still runs and closes the terminal."""
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait()
        for fd in (self.slave_fd, self.master_fd):
            if fd is not None:
                try:
                    os.close(fd)
                except OSError:
                    pass

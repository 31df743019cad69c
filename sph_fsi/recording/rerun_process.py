"""A RerunSink in a child process, for a process that opens many recordings (the node: one per ~/reset).

rerun-sdk 0.41 keeps about 0.35 MB of native memory for every RecordingStream it has created, after the stream
is flushed, disconnected and dropped (measured: 400 streams with no data logged take the resident memory from
100 to 229 MB, linearly; one stream reused with a new file sink each time stays flat). The node's memory grew
with every reset that recorded to Rerun. Here each recording's stream lives in its own child process, which
exits when the recording closes, and its memory with it. The child is `python -m sph_fsi.recording.rerun_process`
on one end of a socket pair (not multiprocessing's spawn, which re-imports the parent's main script).

The child gets the items (recording.frame's Static, Frame, Final) through a socket and writes them with RerunSink.
Starting it (importing rerun and numba, about 1-2 s of CPU) does not hold up the caller: items wait in the socket.
A failure to open the stream or to write comes back on the next write (or at close) and stops this sink
(BackgroundWriter drops it and logs why); the caller checks the paths first (the node checks them at startup, and
its first recording is in-process, so that a bad path is refused there).
"""
import socket
import subprocess
import sys
from multiprocessing.connection import Connection

__all__ = ["RerunProcessSink"]

OPEN_TIMEOUT = 120.0    # s: the child imports rerun and numba's cached kernels before it reads
CLOSE_TIMEOUT = 120.0   # s: the child flushes the stream


def _serve(conn):
    from .rerun_sink import RerunSink
    rrd_path, connect = conn.recv()
    try:
        sink = RerunSink(rrd_path=rrd_path, connect=connect)
    except Exception as exc:
        conn.send(("error", f"{type(exc).__name__}: {exc}"))
        return
    conn.send(("ready", None))
    failed = None
    while True:
        try:
            kind, item = conn.recv()
        except EOFError:          # the parent went away: end the file as it is
            kind = "close"
        if kind == "close":
            try:
                sink.close()
            except Exception as exc:
                failed = failed or f"{type(exc).__name__}: {exc}"
            try:
                conn.send(("closed", (sink.frames, failed)))
            except (BrokenPipeError, OSError):
                pass
            return
        if failed is None:
            try:
                sink.write(item)
            except Exception as exc:
                failed = f"{type(exc).__name__}: {exc}"
                conn.send(("error", failed))


class RerunProcessSink:
    """RerunSink's interface (write, close, frames, path), the stream in a child process."""

    def __init__(self, rrd_path=None, connect=None):
        if not rrd_path and not connect:
            raise ValueError("RerunSink needs an .rrd path or a viewer address")
        self.path = str(rrd_path) if rrd_path else None
        self.frames = 0
        self._closed = False
        ours, theirs = socket.socketpair()
        try:
            self._proc = subprocess.Popen([sys.executable, "-m", __name__, str(theirs.fileno())],
                                          pass_fds=(theirs.fileno(),), stdin=subprocess.DEVNULL)
        finally:
            theirs.close()
        self._conn = Connection(ours.detach())
        self._conn.send((self.path, connect))

    def write(self, item):
        while self._conn.poll():
            kind, detail = self._conn.recv()
            if kind == "error":
                raise RuntimeError(detail)
        self._conn.send(("write", item))
        if type(item).__name__ == "Frame":
            self.frames += 1

    def close(self):
        if self._closed:
            return
        self._closed = True
        failed = None
        try:
            self._conn.send(("close", None))
            while self._conn.poll(OPEN_TIMEOUT + CLOSE_TIMEOUT):
                kind, detail = self._conn.recv()
                if kind == "closed":
                    self.frames, failed = detail
                    break
                if kind == "error":
                    failed = detail
            else:
                failed = f"the Rerun recorder process did not finish the file within {CLOSE_TIMEOUT:g} s"
        except (BrokenPipeError, EOFError, OSError) as exc:
            failed = f"the Rerun recorder process ended early ({type(exc).__name__})"
        finally:
            try:
                self._proc.wait(10.0)
            except subprocess.TimeoutExpired:
                self._kill()
            self._conn.close()
        if failed:
            raise RuntimeError(failed)

    def _kill(self):
        self._proc.kill()
        self._proc.wait(5.0)


if __name__ == "__main__":
    _serve(Connection(int(sys.argv[1])))

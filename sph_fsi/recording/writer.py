"""A background writer: one thread that feeds items from a bounded queue to the sinks (MCAP, Rerun).

The simulation thread calls `submit()`, which returns at once while the queue has room. When it is full the
simulator waits for the disk (nothing is dropped), and the first time that happens a warning says so with the
counts; `stats()` reports how often and how long it waited. `close()` lets the thread write what is queued,
closes every sink on that thread (files end whole: MCAP summary and footer, Rerun footer) and joins it.

A sink is an object with `write(item)` and `close()`. A sink that raises is reported once, closed, and dropped;
the others go on.
"""
import queue
import sys
import threading
import time

__all__ = ["BackgroundWriter"]

_STOP = object()


def _stderr(msg):
    sys.stderr.write(msg + "\n")
    sys.stderr.flush()


class BackgroundWriter:
    def __init__(self, sinks, max_queue=8, log=None, name="recorder"):
        self.sinks = list(sinks)
        self.max_queue = max_queue
        self._log = log or _stderr
        self._q = queue.Queue(maxsize=max_queue)
        self.submitted = 0
        self.written = 0
        self.waits = 0
        self.wait_seconds = 0.0
        self.write_seconds = 0.0
        self.errors = []
        self._warned = False
        self._closed = False
        self._thread = threading.Thread(target=self._run, name=name, daemon=True)
        self._thread.start()

    def submit(self, item):
        """Queue `item`; waits only when the queue is full (and then warns once, with counts)."""
        if self._closed:
            raise RuntimeError("recorder closed")
        self.submitted += 1
        try:
            self._q.put_nowait(item)
            return
        except queue.Full:
            pass
        if not self._warned:
            self._warned = True
            self._log(f"recording: queue full ({self.max_queue} frames waiting, {self.written} of "
                      f"{self.submitted - 1} written): the simulator now waits for the recorder; consider a larger "
                      f"record interval or lighter compression")
        t0 = time.perf_counter()
        self._q.put(item)
        self.waits += 1
        self.wait_seconds += time.perf_counter() - t0

    def _run(self):
        try:
            while True:
                item = self._q.get()
                if item is _STOP:
                    break
                t0 = time.perf_counter()
                for sink in list(self.sinks):
                    try:
                        sink.write(item)
                    except Exception as exc:   # report, close and drop this sink; keep the others
                        self._fail(sink, exc)
                self.write_seconds += time.perf_counter() - t0
                self.written += 1
        finally:
            for sink in self.sinks:
                try:
                    sink.close()
                except Exception as exc:
                    self.errors.append(f"{type(sink).__name__} close: {type(exc).__name__}: {exc}")
                    self._log(f"recording: closing {type(sink).__name__} failed: {type(exc).__name__}: {exc}")

    def _fail(self, sink, exc):
        self.errors.append(f"{type(sink).__name__}: {type(exc).__name__}: {exc}")
        self._log(f"recording: {type(sink).__name__} stopped: {type(exc).__name__}: {exc}")
        self.sinks.remove(sink)
        try:
            sink.close()
        except Exception:
            pass

    def close(self, timeout=None):
        """Write what is queued, close the sinks, join the thread. Idempotent."""
        if not self._closed:
            self._closed = True
            self._q.put(_STOP)
        self._thread.join(timeout)
        return self.stats()

    @property
    def alive(self):
        return self._thread.is_alive()

    def stats(self):
        return {"submitted": self.submitted, "written": self.written, "waits": self.waits,
                "wait_seconds": self.wait_seconds, "write_seconds": self.write_seconds, "errors": list(self.errors)}

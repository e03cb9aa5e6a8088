"""A UDP proxy that makes a link lossy, independent of rotorpilot's own `--link-loss`: what a
client sends to `client_port` goes to the vehicle, what the vehicle sends back to the proxy goes
to the client; each datagram is dropped with probability `loss`, sent twice with `duplicate`,
and each copy held for a delay uniform in [0, `delay_s`] (so datagrams overtake each other),
all drawn from `random.Random(seed)`. Counts what it did in `counts`."""
from __future__ import annotations

import heapq
import random
import socket
import threading
import time


class LossyProxy:
    """Between one client and the vehicle's UDP link at `vehicle` (host, port)."""

    def __init__(self, vehicle: tuple[str, int], *, loss: float, duplicate: float, delay_s: float,
                 seed: int) -> None:
        self.vehicle = vehicle
        self.loss, self.duplicate, self.delay_s = loss, duplicate, delay_s
        self.rng = random.Random(seed)
        self.client_side = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.client_side.bind(("127.0.0.1", 0))
        self.vehicle_side = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.vehicle_side.bind(("127.0.0.1", 0))
        for s in (self.client_side, self.vehicle_side):
            s.settimeout(0.005)
        self.client: tuple[str, int] | None = None
        self.counts = {"datagrams": 0, "dropped": 0, "duplicated": 0}
        self._held: list[tuple[float, int, socket.socket, bytes, tuple[str, int]]] = []
        self._order = 0
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    @property
    def client_port(self) -> int:
        """Where the client sends (its connection string: ``udpout:127.0.0.1:PORT``)."""
        return int(self.client_side.getsockname()[1])

    def _offer(self, out: socket.socket, data: bytes, to: tuple[str, int]) -> None:
        self.counts["datagrams"] += 1
        if self.rng.random() < self.loss:
            self.counts["dropped"] += 1
            return
        copies = 2 if self.rng.random() < self.duplicate else 1
        self.counts["duplicated"] += copies - 1
        for _ in range(copies):
            self._order += 1
            heapq.heappush(self._held, (time.monotonic() + self.rng.uniform(0.0, self.delay_s), self._order, out,
                                        data, to))

    def _run(self) -> None:
        while not self._stop.is_set():
            for sock in (self.client_side, self.vehicle_side):
                try:
                    data, sender = sock.recvfrom(65536)
                except (socket.timeout, BlockingIOError):
                    continue
                except OSError:
                    return
                if sock is self.client_side:
                    self.client = sender
                    self._offer(self.vehicle_side, data, self.vehicle)
                elif self.client is not None:
                    self._offer(self.client_side, data, self.client)
            now = time.monotonic()
            while self._held and self._held[0][0] <= now:
                _, _, out, data, to = heapq.heappop(self._held)
                try:
                    out.sendto(data, to)
                except OSError:
                    pass

    def close(self) -> None:
        self._stop.set()
        self._thread.join(timeout=2)
        self.client_side.close()
        self.vehicle_side.close()

"""Issue 34, item 7: ``--scheduler`` at a TCP service that is not Dask.

Before, ``sso sweep --scheduler`` at an HTTP server answering ``400`` ended in
numpy's ``_ArrayMemoryError: Unable to allocate 3.07 EiB`` (distributed read
``HTTP/1.1`` as the length of a message and allocated it). The servers here are real,
on 127.0.0.1, started by the test; the Dask scheduler is distributed's own.
"""

from __future__ import annotations

import asyncio
import socket
import socketserver
import subprocess
import sys
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest

from sso._studies.dask_handshake import check_dask_scheduler, client_handshake

ROOT = Path(__file__).resolve().parents[2]
CASE = ROOT / "cases" / "paper_option1_exact.toml"
BAD_REQUEST = (b"HTTP/1.1 400 Bad Request\r\nContent-Type: text/plain\r\n"
               b"Content-Length: 11\r\nConnection: close\r\n\r\nBad Request")


class _AnswersBadRequest(socketserver.BaseRequestHandler):
    """An HTTP server's answer to bytes that are no HTTP request: 400, then close."""

    def handle(self) -> None:
        self.request.settimeout(5)
        self.request.recv(65536)
        self.request.sendall(BAD_REQUEST)


class _HangsUp(socketserver.BaseRequestHandler):
    def handle(self) -> None:
        pass  # closes the connection without a word


class _Silent(socketserver.BaseRequestHandler):
    def handle(self) -> None:
        self.request.settimeout(5)
        try:
            while self.request.recv(65536):  # reads, says nothing, until the client leaves
                pass
        except OSError:
            pass


@contextmanager
def serving(handler: type[socketserver.BaseRequestHandler]) -> Iterator[str]:
    """A TCP server on 127.0.0.1 with ``handler``; yields its tcp:// address."""
    server = socketserver.ThreadingTCPServer(("127.0.0.1", 0), handler)
    server.daemon_threads = True
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"tcp://127.0.0.1:{server.server_address[1]}"
    finally:
        server.shutdown()
        server.server_close()


def test_sso_sweep_at_an_http_server_answering_400_is_bad_input(tmp_path):
    (tmp_path / "s.toml").write_text(f'name = "s"\ncase = "{CASE}"\naction = "evaluate"\n\n'
                                     "[axes]\ninput_speed_rpm = [10, 20]\n")
    with serving(_AnswersBadRequest) as address:
        done = subprocess.run([sys.executable, "-m", "sso", "sweep", "s.toml", "--scheduler",
                               address, "--no-plots", "--quiet"], cwd=tmp_path,
                              capture_output=True, text=True, timeout=120)
    assert done.returncode == 2, done.stderr
    assert "Traceback" not in done.stderr and "allocate" not in done.stderr
    assert (f"error: s.toml: scheduler = {address!r} is not a Dask scheduler: it answered "
            "b'HTTP/1.1 400 Bad Request\\r\\nContent-Type: ' where a Dask scheduler sends "
            "its handshake") in done.stderr
    assert not (tmp_path / "results" / "s").exists()  # nothing started


def test_a_service_that_hangs_up_or_stays_silent_is_named(tmp_path):
    with serving(_HangsUp) as address, pytest.raises(ValueError) as refused:
        check_dask_scheduler(address)
    assert str(refused.value) == (f"scheduler = {address!r} is not a Dask scheduler: it "
                                  "answered nothing (it closed the connection) where a Dask "
                                  "scheduler sends its handshake")
    with serving(_Silent) as address, pytest.raises(ValueError) as refused:
        check_dask_scheduler(address, timeout_s=0.3)
    assert str(refused.value) == (f"scheduler = {address!r} sent no Dask handshake within "
                                  "0.3 s: it is not a Dask scheduler, or too slow to reach")


def test_a_closed_port_and_a_malformed_address_are_named():
    with socket.socket() as probe:  # a port nobody listens on: bound, never listening
        probe.bind(("127.0.0.1", 0))
        address = f"tcp://127.0.0.1:{probe.getsockname()[1]}"
        with pytest.raises(ValueError, match="cannot be reached: Connection refused"):
            check_dask_scheduler(address)
    with pytest.raises(ValueError, match="give the scheduler's address as tcp://HOST:PORT"):
        check_dask_scheduler("tcp://127.0.0.1:http")


def test_a_real_dask_scheduler_passes_and_its_handshake_is_the_clients():
    distributed = pytest.importorskip("distributed")
    from distributed.comm.utils import from_frames
    from distributed.protocol.utils import unpack_frames

    with distributed.LocalCluster(n_workers=0, processes=False, protocol="tcp",
                                  host="127.0.0.1", dashboard_address=None) as cluster:
        check_dask_scheduler(cluster.scheduler_address)
    # What sso sends is what distributed's client sends (read back by distributed itself:
    # the length, the frames, the message).
    sent = client_handshake()
    assert int.from_bytes(sent[:8], "little") == len(sent) - 8
    decoded = asyncio.run(from_frames(unpack_frames(sent[8:]), deserialize=False))
    assert decoded == {"compression": None, "python": tuple(sys.version_info[:3]),
                       "pickle-protocol": 5}

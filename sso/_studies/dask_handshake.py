"""Whether an address is a Dask scheduler, from the first bytes it sends, before
dask.distributed is given the address.

A Dask scheduler speaks first: on a new TCP connection it sends its handshake, a
message framed as distributed frames every message (``distributed.comm.tcp``): its
length in bytes (8 bytes, little-endian), the number of frames (8 bytes), each
frame's length (8 bytes each), then the frames; the handshake is one small msgpack
map naming ``compression``, ``python`` and ``pickle-protocol`` (58 bytes from
distributed 2026.8). distributed's client reads that length and allocates it before
it checks anything, so a service that is not Dask (an HTTP server answering
``HTTP/1.1 400``, read as a length of 3.5e18 bytes) made it try to allocate 3.07 EiB.
Here the client's handshake is sent, as distributed's client sends it (a service that
waits for its client to speak answers it: an HTTP server with ``400 Bad Request``), and
at most :data:`LARGEST_HANDSHAKE_BYTES` are read back, within a time limit.
"""

from __future__ import annotations

import socket
import struct
import sys
import time

HANDSHAKE_TIMEOUT_S = 10.0
"""How long the scheduler has to connect and send its handshake (distributed's own
client allows 10 s to connect)."""
LARGEST_HANDSHAKE_BYTES = 65_536
"""The largest handshake believed (a scheduler's is under 100 bytes)."""
SHOWN_BYTES = 40
"""How much of a stranger's answer an error shows."""
_HANDSHAKE_KEYS = (b"compression", b"python", b"pickle-protocol")


def client_handshake() -> bytes:
    """The handshake distributed's client sends, framed: a msgpack map of no
    compression, this Python's version and pickle protocol 5."""
    version = bytes(sys.version_info[:3])  # each below 128: msgpack positive fixints
    body = (b"\x83\xabcompression\xc0\xa6python\x93" + version
            + b"\xafpickle-protocol\x05")
    frames = struct.pack("<QQ", 1, len(body)) + body
    return struct.pack("<Q", len(frames)) + frames


def check_dask_scheduler(address: str, timeout_s: float = HANDSHAKE_TIMEOUT_S) -> None:
    """Raise unless ``address`` answers a TCP connection with a Dask handshake.

    Addresses of another protocol (``tls://``, ``ws://``, ``inproc://``...) are
    left to dask.distributed as given: their handshake is not plain bytes here.

    Parameters
    ----------
    address : str
        ``tcp://HOST:PORT``, or ``HOST:PORT`` (TCP, as dask reads it).
    timeout_s : float
        Seconds to connect and receive the handshake.

    Raises
    ------
    ValueError
        Naming the address and what came back instead (nothing, too much, bytes that
        are not Dask's, a refused or timed-out connection), or a malformed address.
    """
    scheme, separator, location = address.partition("://")
    if not separator:
        scheme, location = "tcp", address
    if scheme != "tcp":
        return
    host, port = _host_and_port(address, location)
    deadline = time.monotonic() + timeout_s
    try:
        with socket.create_connection((host, port), timeout=timeout_s) as connection:
            try:
                connection.sendall(client_handshake())
            except (BrokenPipeError, ConnectionResetError):
                pass  # it spoke and hung up first: what it said is read below
            first = _receive(connection, 8, deadline)
            (length,) = struct.unpack("<Q", first) if len(first) == 8 else (None,)
            if length is None or not 16 <= length <= LARGEST_HANDSHAKE_BYTES:
                answer = first + _receive(connection, SHOWN_BYTES - len(first),
                                          min(deadline, time.monotonic() + 0.5), quiet=True)
                raise ValueError(f"scheduler = {address!r} is not a Dask scheduler: it "
                                 f"answered {_shown(answer)} where a Dask scheduler "
                                 "sends its handshake")
            message = _receive(connection, length, deadline)
    except TimeoutError:
        raise ValueError(f"scheduler = {address!r} sent no Dask handshake within "
                         f"{timeout_s:g} s: it is not a Dask scheduler, or too slow to "
                         "reach") from None
    except OSError as error:
        raise ValueError(f"scheduler = {address!r} cannot be reached: "
                         f"{error.strerror or error}") from None
    if not _is_handshake(message):
        raise ValueError(f"scheduler = {address!r} is not a Dask scheduler: its first "
                         f"message ({_shown(message)}) is not a Dask handshake")


def _host_and_port(address: str, location: str) -> tuple[str, int]:
    host, _, port = location.rpartition(":")
    host = host.removeprefix("[").removesuffix("]")  # an IPv6 address in brackets
    if not host or not port.isdigit() or not 0 < int(port) < 65536:
        raise ValueError(f"scheduler = {address!r}: give the scheduler's address as "
                         "tcp://HOST:PORT (PORT from 1 to 65535)")
    return host, int(port)


def _receive(connection: socket.socket, size: int, deadline: float,
             quiet: bool = False) -> bytes:
    """Up to ``size`` bytes, fewer only if the peer closed the connection first (or,
    ``quiet``, if the deadline passed or the connection failed)."""
    received = bytearray()
    while len(received) < size:
        remaining_s = deadline - time.monotonic()
        if remaining_s <= 0:
            if quiet:
                break
            raise TimeoutError
        connection.settimeout(remaining_s)
        try:
            chunk = connection.recv(size - len(received))
        except OSError:
            if quiet:
                break
            raise
        if not chunk:
            break
        received += chunk
    return bytes(received)


def _is_handshake(message: bytes) -> bool:
    """Whether ``message`` is framed as distributed frames it and names the handshake's
    keys."""
    if len(message) < 8:
        return False
    (frames,) = struct.unpack_from("<Q", message)
    if not 1 <= frames <= (len(message) - 8) // 8:
        return False
    lengths = struct.unpack_from(f"<{frames}Q", message, 8)
    return (8 + 8 * frames + sum(lengths) == len(message)
            and all(key in message for key in _HANDSHAKE_KEYS))


def _shown(data: bytes) -> str:
    if not data:
        return "nothing (it closed the connection)"
    return repr(data[:SHOWN_BYTES]) + (" ..." if len(data) > SHOWN_BYTES else "")

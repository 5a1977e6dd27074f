"""The doll as a live controller: each tracked frame sent to other programs over OSC.

Open Sound Control over UDP is what live-performance tools speak (Blender's AddRoutes and
NodeOSC, TouchDesigner, Unity, Godot and Unreal receivers). Every tracked frame of a doll is
one OSC bundle (or, without bundles, the same messages one by one) to ``HOST:PORT``:

==============================  ==============  =============================================
address                         arguments       meaning
==============================  ==============  =============================================
``/voodoo/<doll>/frame``        int, float      frame number in the source, its time (s)
``/voodoo/<doll>/pose``         4 floats        translate-x, translate-y (pixels), rotate
                                                (radians, clockwise on screen), log scale
``/voodoo/<doll>/mode/<mode>``  float           each mode's value by its name (``bend-x``):
                                                its shape-key value (in Blender times the
                                                mode's gain, and only the modes that apply)
``/voodoo/<doll>/quality``      float, int      confidence in [0, 1], lost (1) or not (0)
``/voodoo/<doll>/view``         float           share of the doll's mesh in view, in [0, 1]:
                                                less while part of it is folded under,
                                                turned away or covered; 0 when lost
==============================  ==============  =============================================

``<doll>`` and ``<mode>`` are the names with every character OSC reserves (space ``#*,/?[]{}``)
replaced by ``_``. Floats are 32-bit (what every OSC receiver reads).

Sending never holds up tracking: the socket does not block, a datagram the system cannot
take at once is dropped and counted, and an error (an unreachable network, say) is kept as
one message in :attr:`OscSender.warnings` instead of being raised. A target that is not
``HOST:PORT`` or whose name does not resolve is refused when the sender is made
(:class:`~voodoo_addon.errors.VoodooError`), before any frame is tracked.
"""

from __future__ import annotations

import re
import socket

from pythonosc.osc_bundle_builder import IMMEDIATELY, OscBundleBuilder
from pythonosc.osc_message_builder import OscMessageBuilder

from .errors import VoodooError

#: Where the address space starts.
ROOT = "/voodoo"
_RESERVED = re.compile(r"[\s#*,/?\[\]{}]")


def osc_name(name: str) -> str:
    """``name`` as one part of an OSC address (reserved characters become ``_``)."""
    return _RESERVED.sub("_", str(name)) or "_"


def parse_target(text: str) -> tuple[str, int]:
    """``(host, port)`` of ``HOST:PORT`` (``[v6 address]:PORT`` for IPv6).

    Raises
    ------
    VoodooError
        When ``text`` is not of that form or the port is not 1-65535.
    """
    m = re.fullmatch(r"\s*(\[[^\]]+\]|[^:\s]+):(\d{1,5})\s*", str(text))
    if m is None or not 1 <= int(m.group(2)) <= 65535:
        raise VoodooError(
            f"{text!r} is not an OSC target: give HOST:PORT, e.g. 127.0.0.1:9000 (port 1-65535)."
        )
    return m.group(1).strip("[]"), int(m.group(2))


def frame_messages(
    doll: str,
    index: int,
    time: float,
    pose,
    modes: dict,
    confidence: float,
    lost: bool,
    in_view: float | None = None,
) -> list:
    """The OSC messages of one frame (see the module's table), in that order.

    ``pose`` (4,): translate-x, translate-y, rotate, log scale; ``modes``: name -> value;
    ``in_view``: the share of the mesh in view (``/view`` is left out when None).
    """
    base = f"{ROOT}/{osc_name(doll)}"

    def message(address, *args):
        builder = OscMessageBuilder(address)
        for value, kind in args:
            builder.add_arg(value, arg_type=kind)
        return builder.build()

    out = [
        message(f"{base}/frame", (int(index), "i"), (float(time), "f")),
        message(f"{base}/pose", *[(float(v), "f") for v in pose]),
    ]
    out += [message(f"{base}/mode/{osc_name(k)}", (float(v), "f")) for k, v in modes.items()]
    out.append(message(f"{base}/quality", (float(confidence), "f"), (int(bool(lost)), "i")))
    if in_view is not None:
        out.append(message(f"{base}/view", (float(in_view), "f")))
    return out


def view_share(result) -> float:
    """The share of a :class:`~voodoo_addon.tracking.TrackResult`'s triangles in view."""
    if result.lost or result.visible is None or not len(result.visible):
        return 0.0
    return float(result.visible.mean())


class OscSender:
    """Sends frames to one OSC receiver over UDP, never blocking, never raising.

    Parameters
    ----------
    target : str
        ``HOST:PORT``; the host name is resolved once, here.
    bundle : bool
        One bundle per frame (default), or its messages one datagram each.

    Raises
    ------
    VoodooError
        When ``target`` is not ``HOST:PORT`` or its host name does not resolve.
    """

    def __init__(self, target: str, bundle: bool = True):
        host, port = parse_target(target)
        try:
            info = socket.getaddrinfo(host, port, type=socket.SOCK_DGRAM)
        except (OSError, UnicodeError) as exc:
            raise VoodooError(f"The OSC host {host!r} is not known ({exc}).") from None
        family, kind, proto, _, self.address = info[0]
        self.target = f"{host}:{port}"
        self.bundle = bool(bundle)
        self._socket = socket.socket(family, kind, proto)
        self._socket.setblocking(False)
        self.sent = 0  # frames sent whole
        self.dropped = 0  # datagrams the system would not take
        self._warnings: dict[str, str] = {}

    @property
    def warnings(self) -> list[str]:
        """One line for each kind of failure so far (none when every frame went out)."""
        return list(self._warnings.values())

    def send(self, *frame, **named) -> bool:
        """Send one frame (the arguments of :func:`frame_messages`); True if it all went out."""
        messages = frame_messages(*frame, **named)
        if self.bundle:
            builder = OscBundleBuilder(IMMEDIATELY)
            for m in messages:
                builder.add_content(m)
            datagrams = [builder.build().dgram]
        else:
            datagrams = [m.dgram for m in messages]
        whole = True
        for dgram in datagrams:
            try:
                self._socket.sendto(dgram, self.address)
            except BlockingIOError:
                self.dropped += 1
                whole = False
                self._warnings.setdefault(
                    "full", f"OSC to {self.target}: the network could not keep up; frames dropped."
                )
            except OSError as exc:
                self.dropped += 1
                whole = False
                self._warnings.setdefault(
                    type(exc).__name__, f"OSC to {self.target} failed ({exc}); tracking goes on."
                )
        self.sent += whole
        return whole

    def close(self) -> None:
        self._socket.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

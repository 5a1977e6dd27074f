"""A 2-D puppet moved by a voodoo doll over OSC: what a game would do with the stream.

Start it, then stream a doll to it (another terminal)::

    python examples/osc_puppet.py --port 9000 --out out/puppet.mp4
    python -m voodoo_addon live camera:0 --contour doll.json --osc 127.0.0.1:9000

It listens on 127.0.0.1 (``--host`` for another interface), and for every frame of the doll
it receives (``/voodoo/<doll>/pose``, ``.../mode/<name>``, ``.../quality``: see the README's
*Streaming* section) it draws a gingerbread figure with OpenCV: the doll's translation,
rotation and scale move the figure, its first bend, stretch, shear, taper and twist modes
bend, stretch, shear, taper and twist it. Mode values
are scaled by the largest seen so far (every doll has its own range). Frames go to a video
(``--out``) and, where OpenCV has a window system, to a window (``--show``). It stops after
``--frames`` frames or ``--idle`` seconds without any.
"""

import argparse
import math

import cv2
import numpy as np
from pythonosc.dispatcher import Dispatcher
from pythonosc.osc_server import BlockingOSCUDPServer

SIZE = (480, 360)  # the canvas, pixels
#: How far a mode at its largest value moves the figure (fraction of its size), by mode name.
FIELDS = {
    "bend-x": lambda u, v: (0 * u, 0.35 * u * u),
    "bend-y": lambda u, v: (0.35 * v * v, 0 * v),
    "stretch-x": lambda u, v: (0.3 * u, 0 * v),
    "stretch-y": lambda u, v: (0 * u, 0.3 * v),
    "shear": lambda u, v: (0.3 * v, 0 * u),
    "taper-x": lambda u, v: (0 * u, 0.3 * u * v),
    "taper-y": lambda u, v: (0.3 * u * v, 0 * v),
    "twist": lambda u, v: (-0.3 * v * u, 0.3 * u * v),
}


def gingerbread(n: int = 64) -> list[np.ndarray]:
    """The figure's outlines (head, body, two eyes) in [-1, 1] coordinates, y down."""
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    head = np.stack([0.35 * np.cos(t), -0.55 + 0.3 * np.sin(t)], 1)
    body = np.stack([0.55 * np.cos(t), 0.35 + 0.6 * np.sin(t)], 1)
    eye = np.stack([0.06 * np.cos(t), 0.06 * np.sin(t)], 1)
    return [body, head, eye + [-0.13, -0.6], eye + [0.13, -0.6]]


class Puppet:
    """The latest frame of the doll, and the figure drawn from it."""

    def __init__(self):
        self.pose = np.zeros(4)
        self.modes: dict[str, float] = {}
        self.largest: dict[str, float] = {}
        self.frames = 0
        self.confidence = 0.0
        self.lost = False
        self.origin = None  # the doll's first position: the figure starts centred

    def on_pose(self, address, *values):
        self.pose = np.array(values[:4], dtype=float)
        if self.origin is None:
            self.origin = self.pose[:2].copy()

    def on_mode(self, address, value):
        name = address.rsplit("/", 1)[-1]
        self.modes[name] = float(value)
        self.largest[name] = max(self.largest.get(name, 0.0), abs(float(value)), 1e-9)

    def on_quality(self, address, confidence, lost):
        """The last message of a frame: draw it."""
        self.confidence, self.lost = float(confidence), bool(lost)
        self.frames += 1

    def draw(self) -> np.ndarray:
        canvas = np.full((SIZE[1], SIZE[0], 3), 245, np.uint8)
        scale = 0.3 * SIZE[1] * math.exp(self.pose[3])
        turn = np.array(
            [
                [math.cos(self.pose[2]), -math.sin(self.pose[2])],
                [math.sin(self.pose[2]), math.cos(self.pose[2])],
            ]
        )
        shift = np.array(SIZE) / 2 + (
            self.pose[:2] - (self.origin if self.origin is not None else 0)
        )
        colours = [(60, 110, 190), (60, 110, 190), (30, 30, 30), (30, 30, 30)]
        for outline, colour in zip(gingerbread(), colours, strict=True):
            u, v = outline[:, 0], outline[:, 1]
            du, dv = np.zeros_like(u), np.zeros_like(v)
            for name, value in self.modes.items():
                field = FIELDS.get(name)  # the first mode of each kind (not "bend-x_2")
                if field is not None:
                    fu, fv = field(u, v)
                    du += fu * value / self.largest[name]
                    dv += fv * value / self.largest[name]
            local = np.stack([u + du, v + dv], 1) * scale
            points = local @ turn.T + shift
            cv2.fillPoly(canvas, [np.round(points).astype(np.int32)], colour, cv2.LINE_AA)
        text = f"frame {self.frames}  confidence {self.confidence:.2f}" + (
            "  LOST" if self.lost else ""
        )
        cv2.putText(canvas, text, (8, 20), cv2.FONT_HERSHEY_SIMPLEX, 0.5, (0, 0, 0), 1, cv2.LINE_AA)
        return canvas


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--host", default="127.0.0.1", help="address to listen on")
    p.add_argument("--port", type=int, default=9000)
    p.add_argument("--out", help="write the puppet's frames to this video (.mp4)")
    p.add_argument("--show", action="store_true", help="also show them in a window")
    p.add_argument("--frames", type=int, help="stop after this many frames")
    p.add_argument("--idle", type=float, default=10.0, help="stop after this long without a frame")
    args = p.parse_args(argv)

    puppet = Puppet()
    dispatcher = Dispatcher()
    dispatcher.map("/voodoo/*/pose", puppet.on_pose)
    dispatcher.map("/voodoo/*/mode/*", puppet.on_mode)
    dispatcher.map("/voodoo/*/quality", puppet.on_quality)
    server = BlockingOSCUDPServer((args.host, args.port), dispatcher)
    server.timeout = 0.1
    print(f"osc_puppet: listening on {args.host}:{server.server_address[1]}", flush=True)
    writer = None
    if args.out:
        writer = cv2.VideoWriter(args.out, cv2.VideoWriter_fourcc(*"mp4v"), 30.0, SIZE)
    idle, drawn = 0.0, 0
    try:
        while idle < args.idle and (args.frames is None or drawn < args.frames):
            server.handle_request()
            if puppet.frames == drawn:
                idle += server.timeout
                continue
            idle, drawn = 0.0, puppet.frames
            picture = puppet.draw()
            if writer is not None:
                writer.write(picture)
            if args.show:
                cv2.imshow("osc_puppet", picture)
                cv2.waitKey(1)
    except KeyboardInterrupt:
        pass
    finally:
        server.server_close()
        if writer is not None:
            writer.release()
    print(f"osc_puppet: {drawn} frames drawn, modes seen: {', '.join(sorted(puppet.modes))}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

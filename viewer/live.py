"""Live mode: a meshcat server on 127.0.0.1 and a stream of body poses.

:class:`LiveViewer` starts its own server process (``python -m viewer._server``: HTTP and
zmq on the loopback interface only, output discarded so no pipe can fill, exits when its
parent dies), connects one zmq socket with send and receive timeouts, draws the model's
scene and then sends one transform per body and frame. ``close()`` (or leaving the
``with`` block) stops the server's whole process group and waits for it, within bounds.
"""
from __future__ import annotations

import os
import selectors
import signal
import subprocess
import sys
import time
import weakref
from pathlib import Path

import numpy as np

from viewer import kinematics as kin
from viewer import scene as sc
from viewer.motion import as_recording, parents_of


class ServerError(RuntimeError):
    """The meshcat server did not start or stopped answering."""


def start_server(timeout: float = 20.0, web_port: int | None = None) -> tuple[subprocess.Popen, dict]:
    """Start ``viewer._server`` in its own process group; returns (process, its JSON line)."""
    import json

    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(Path(__file__).resolve().parents[1]), env.get("PYTHONPATH", "")])
    args = [sys.executable, "-m", "viewer._server", "--parent", str(os.getpid())]
    if web_port is not None:
        args += ["--web-port", str(int(web_port))]
    proc = subprocess.Popen(args, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                            env=env, start_new_session=True)
    try:
        line = _read_line(proc, timeout)
        return proc, json.loads(line)
    except BaseException:
        stop_server(proc)
        raise


def _read_line(proc: subprocess.Popen, timeout: float) -> str:
    deadline, data = time.monotonic() + timeout, b""
    with selectors.DefaultSelector() as sel:
        sel.register(proc.stdout, selectors.EVENT_READ)
        while b"\n" not in data:
            left = deadline - time.monotonic()
            if left <= 0 or not sel.select(left):
                raise ServerError(f"the meshcat server did not start within {timeout} s")
            chunk = os.read(proc.stdout.fileno(), 4096)
            if not chunk:
                raise ServerError(f"the meshcat server exited during start-up (exit code {proc.wait(5)})")
            data += chunk
    return data.split(b"\n", 1)[0].decode()


def stop_server(proc: subprocess.Popen, timeout: float = 5.0) -> None:
    """Terminate the server's process group (SIGTERM, then SIGKILL) and reap it."""
    for sig in (signal.SIGTERM, signal.SIGKILL):
        if proc.poll() is not None:
            break
        try:
            os.killpg(proc.pid, sig)
        except ProcessLookupError:
            break
        try:
            proc.wait(timeout)
        except subprocess.TimeoutExpired:
            continue
    if proc.stdout:
        proc.stdout.close()


class Connection:
    """One zmq REQ socket to a meshcat server, with timeouts; ``send`` takes meshcat commands."""

    def __init__(self, zmq_url: str, timeout: float = 5.0):
        import zmq

        self._zmq, self.timeout, self.broken = zmq, timeout, False
        self.context = zmq.Context()
        self.socket = self.context.socket(zmq.REQ)
        for opt, value in ((zmq.RCVTIMEO, int(timeout * 1000)), (zmq.SNDTIMEO, int(timeout * 1000)), (zmq.LINGER, 0)):
            self.socket.setsockopt(opt, value)
        self.socket.connect(zmq_url)

    def request(self, frames: list[bytes]) -> bytes:
        if self.broken:
            raise ServerError("the meshcat connection timed out earlier; open a new viewer")
        try:
            self.socket.send_multipart(frames)
            return self.socket.recv()
        except self._zmq.error.Again:
            self.broken = True
            raise ServerError(f"the meshcat server did not answer within {self.timeout} s") from None

    def send(self, command) -> None:
        import umsgpack

        data = command if isinstance(command, dict) else command.lower()
        self.request([data["type"].encode(), data["path"].encode(), umsgpack.packb(data)])

    def close(self) -> None:
        self.socket.close(linger=0)
        self.context.term()


def _shutdown(proc, conn) -> None:
    conn.close()
    if proc is not None:
        stop_server(proc)


class LiveViewer:
    """Stream the poses of ``system`` (a :class:`mbs.System`) to a meshcat server.

    Without ``zmq_url`` a private server is started on 127.0.0.1 (``url`` is its page; the
    web port is the first free one from 7000 unless ``web_port`` is given). ``timeout`` (s)
    bounds every request; ``flat`` and ``follow`` as in :func:`viewer.scene.build_scene`.
    """

    def __init__(self, system, zmq_url: str | None = None, flat: bool = False, follow=True,
                 timeout: float = 5.0, startup_timeout: float = 20.0, web_port: int | None = None):
        self.system, self.parents = system, parents_of(system.info)
        self.scene = sc.build_scene(system.info, flat, trace=False, follow=follow)
        self.process, self.url = None, None
        if zmq_url is None:
            self.process, meta = start_server(startup_timeout, web_port)
            zmq_url, self.url = meta["zmq_url"], meta["web_url"]
        self.zmq_url = zmq_url
        self.connection = Connection(zmq_url, timeout)
        self._finalizer = weakref.finalize(self, _shutdown, self.process, self.connection)
        try:
            if self.url is None:
                self.url = self.connection.request([b"url"]).decode()
            self._draw()
        except BaseException:
            self.close()
            raise

    @property
    def pid(self) -> int | None:
        """Process id (and process group id) of the private server, if any."""
        return None if self.process is None else self.process.pid

    def _draw(self) -> None:
        mc = sc.meshcat()
        self.connection.send({"type": "set_animation", "path": "", "animations": [],
                              "options": {"play": False, "repetitions": 1}})  # no stale animation
        self.connection.send(mc.commands.Delete(mc.path.Path(("meshcat", "model"))))
        x = self.system.x0()
        origins, rotations = self.system.poses(x, 0.0)
        local, world = self._transforms(origins, rotations)
        for command in sc.commands(self.scene, local, world):
            self.connection.send(command)

    def _transforms(self, origins, rotations) -> tuple[np.ndarray, np.ndarray]:
        nb = len(self.parents)
        origins, rotations = np.asarray(origins, dtype=float), np.asarray(rotations, dtype=float)
        if origins.shape != (nb, 3) or rotations.shape != (nb, 3, 3):
            raise ValueError(f"poses must have shapes ({nb}, 3) and ({nb}, 3, 3), got {origins.shape}, {rotations.shape}")
        if not (np.all(np.isfinite(origins)) and np.all(np.isfinite(rotations))):
            raise ValueError("poses contain non-finite values")
        local = kin.relative(kin.homogeneous(origins, rotations), self.parents)
        world = np.eye(4)
        if self.scene.follow is not None:
            world[:3, 3] = -origins[self.scene.body_names.index(self.scene.follow)]
        return local, world

    def show_poses(self, origins, rotations) -> None:
        """Send body origins (nb, 3) m and rotations body->world (nb, 3, 3), world frame NED."""
        mc = sc.meshcat()
        Path = mc.path.Path
        local, world = self._transforms(origins, rotations)
        if self.scene.follow is not None:
            self.connection.send(mc.commands.SetTransform(world, Path(tuple(sc.WORLD.strip("/").split("/")))))
        for i, name in enumerate(self.scene.body_names):
            self.connection.send(mc.commands.SetTransform(local[i], Path(tuple(self.scene.paths[name].strip("/").split("/")))))

    def show(self, x, t: float = 0.0, p=None) -> None:
        """Send the poses of state ``x`` (nx,) at time ``t`` (s) with parameters ``p``."""
        self.show_poses(*self.system.poses(x, t, p))

    def play(self, source, slow: float = 10.0, revs: float | None = None, every: int = 1) -> int:
        """Replay a Motion, Simulation, results path or Recording at ``slow`` times slower
        than real time (frames that fall behind the clock are dropped); returns the frames sent."""
        from viewer.motion import Motion, motion

        mo = source if isinstance(source, Motion) else motion(as_recording(source), revs, every=every)
        start, sent = time.monotonic(), 0
        for k, t in enumerate(mo.t):
            due = start + (t - mo.t[0]) * slow
            now = time.monotonic()
            if now > due + 0.05 and k < len(mo.t) - 1:
                continue
            time.sleep(max(0.0, due - now))
            self.show_poses(mo.origins[k], mo.rotations[k])
            sent += 1
        return sent

    def simulate(self, scene, revs: float = 1.0, steps_per_rev: int | None = None, params: dict | None = None,
                 slow: float = 10.0, frame_steps: int = 1, progress=None):
        """Run ``scene`` (with this viewer's system) and show every ``frame_steps``-th step as
        it is computed, no faster than ``slow`` times slower than real time. Returns the
        final (t, x)."""
        from mbs import scenes

        scene = scenes.get(scene) if isinstance(scene, str) else scene
        p = self.system.params(params or {})
        steps_per_rev = steps_per_rev or scene.steps_per_rev
        h = scene.revolution(self.system, p) / steps_per_rev
        n, k, t, x = int(round(revs * steps_per_rev)), 0, 0.0, self.system.x0()
        start = time.monotonic()
        while k < n:
            m = min(frame_steps, n - k)
            traj = self.system.run(x, t, h, m, every=m, p=p)
            if not traj.ok:
                raise FloatingPointError(traj.message)
            k, t, x = k + m, float(traj.t[-1]), traj.x[-1]
            time.sleep(max(0.0, start + t * slow - time.monotonic()))
            self.show(x, t, p)
            if progress:
                progress(k, n)
        return t, x

    def close(self) -> None:
        """Close the socket and stop the private server (idempotent)."""
        self._finalizer()

    def __enter__(self) -> "LiveViewer":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

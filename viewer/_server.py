"""meshcat's websocket bridge, listening on 127.0.0.1 only and exiting with its parent.

Run as ``python -m viewer._server --parent PID``. Prints one JSON line
``{"zmq_url": ..., "web_url": ...}`` on stdout, then sends stdout and stderr to /dev/null
(meshcat logs every browser connection; an unread pipe would fill and block the server).
Stops when the parent process is gone, so a killed parent leaves no server behind.
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import warnings


def _bridge_class():
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", category=DeprecationWarning)
        import tornado.web
        from meshcat.servers import zmqserver as zs

    class LoopbackApp(tornado.web.Application):
        def listen(self, port, address=None, **kwargs):
            return super().listen(port, "127.0.0.1", **kwargs)

    class LoopbackBridge(zs.ZMQWebSocketBridge):
        def make_app(self):
            return LoopbackApp([
                (r"/static/(.*)", zs.StaticFileHandlerNoCache, {"path": zs.VIEWER_ROOT, "default_filename": zs.VIEWER_HTML}),
                (r"/", zs.WebSocketHandler, {"bridge": self}),
            ])

    return LoopbackBridge


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--parent", type=int, required=True, help="exit when this process is gone")
    ap.add_argument("--web-port", type=int, default=None, help="HTTP port (default: first free from 7000)")
    args = ap.parse_args(argv)
    import tornado.ioloop

    bridge = _bridge_class()(host="127.0.0.1", port=args.web_port)
    print(json.dumps({"zmq_url": bridge.zmq_url, "web_url": bridge.web_url, "pid": os.getpid()}), flush=True)
    null = os.open(os.devnull, os.O_WRONLY)
    os.dup2(null, 1)
    os.dup2(null, 2)

    def watch_parent():
        if os.getppid() != args.parent:
            bridge.ioloop.stop()

    tornado.ioloop.PeriodicCallback(watch_parent, 250).start()
    try:
        bridge.run()
    finally:
        sys.stdout.flush()
        os._exit(0)


if __name__ == "__main__":
    main()

"""The Dask client a sweep runs on: a local cluster of worker processes or an existing one.

Local clusters have one thread per worker process (the models hold ctypes buffers and the
GIL would serialise threads anyway), no dashboard, and the client's compiled-model cache as
``$MBS_CACHE_DIR``. Their workers' scratch space is Dask's default temporary folder, never
the package's folders.
"""
from __future__ import annotations

import logging
import os
import warnings
from contextlib import contextmanager
from typing import Iterator


def default_workers() -> int:
    """The number of local worker processes by default: the machine's cores."""
    return os.cpu_count() or 1


@contextmanager
def connect(workers: int | None = None, scheduler: str | None = None, client=None) -> Iterator:
    """A :class:`distributed.Client`: ``client`` itself when given, else one connected to the
    scheduler at ``scheduler`` (``tcp://host:port``), else a new local cluster of ``workers``
    processes (default: :func:`default_workers`), closed on exit."""
    if client is not None:
        yield client
        return
    from distributed import Client

    if scheduler:
        with Client(scheduler) as c:
            yield c
        return
    with local_cluster(workers or default_workers()) as cluster, Client(cluster) as c:
        yield c


def local_cluster(workers: int):
    """A :class:`distributed.LocalCluster` of ``workers`` single-threaded processes."""
    from distributed import LocalCluster

    from mbs.backends.compiled import cache_dir

    if workers < 1:
        raise ValueError(f"a local cluster needs >= 1 worker, not {workers}")
    with warnings.catch_warnings():  # the scheduler's HTTP port is taken by another cluster: it uses another
        warnings.filterwarnings("ignore", "Port .* is already in use")
        return LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None,
                            silence_logs=logging.ERROR, env={"MBS_CACHE_DIR": str(cache_dir())})

"""The options of a local Dask cluster: single-threaded worker processes on the loopback
address, no dashboard, and the scheduler's HTTP server (health routes) on a free loopback port,
so that two clusters on one machine never ask for the same port (Dask's default is 8787)."""

from __future__ import annotations

import logging


def local_cluster_options(n_workers: int) -> dict:
    """Keyword arguments of ``distributed.LocalCluster`` for ``n_workers`` workers."""
    return {"n_workers": n_workers, "threads_per_worker": 1, "processes": True,
            "host": "127.0.0.1", "dashboard_address": None,
            "scheduler_kwargs": {"dashboard": False, "dashboard_address": "127.0.0.1:0"},
            "silence_logs": logging.ERROR}

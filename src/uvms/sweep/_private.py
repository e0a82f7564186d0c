"""Dask nodes without an HTTP server, for the private local cluster of :mod:`uvms.sweep.cluster`.

``distributed`` starts an HTTP server in every scheduler and worker (the dashboard, Prometheus metrics, health,
information and proxy routes; the scheduler on port 8787), whatever ``dashboard_address`` says. These
subclasses replace that one hook, so nothing listens but the TLS comm ports. A separate module because it
imports ``distributed`` at the top: the worker processes import :class:`PrivateWorker` by name.
"""

from __future__ import annotations

from distributed import Scheduler, Worker


class _NoHttp:
    def start_http_server(self, routes, dashboard_address, default_port=0, ssl_options=None) -> None:
        """Start nothing: no HTTP port (see the module docstring)."""
        self.http_server = None


class PrivateScheduler(_NoHttp, Scheduler):
    """A scheduler without an HTTP server."""


class PrivateWorker(_NoHttp, Worker):
    """A worker without an HTTP server."""

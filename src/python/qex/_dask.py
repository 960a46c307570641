"""The Dask client that qex.batch and qex.conform share: a running scheduler's, or a LocalCluster's."""

from __future__ import annotations

import contextlib
import importlib
import os
from typing import Any, Iterator, Optional


def distributed() -> Any:
    """dask.distributed, imported on first use: Dask is optional (python3-distributed) and partly
    annotated, so its module is typed Any."""
    return importlib.import_module("dask.distributed")


@contextlib.contextmanager
def client(scheduler: Optional[str], workers: Optional[int], **cluster_options: Any) -> Iterator[Any]:
    """A client of the scheduler at `scheduler`, else of a LocalCluster of `workers` processes (default:
    one per core) with one thread each; closed, with its cluster, on leaving."""
    dd = distributed()
    cluster = None
    if scheduler:
        c = dd.Client(scheduler)
    else:
        cluster = dd.LocalCluster(n_workers=workers or os.cpu_count() or 1, threads_per_worker=1, processes=True,
                                  dashboard_address=None, **cluster_options)
        c = dd.Client(cluster)
    try:
        yield c
    finally:
        c.close()
        if cluster is not None:
            cluster.close()

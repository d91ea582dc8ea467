"""The Dask cluster the examples run on: an existing one given by its scheduler's address
(`dask scheduler`, `dask worker` on many machines), or a LocalCluster on this machine."""

import contextlib
import tempfile


def add_cluster_options(parser, threads=False):
    """--workers, --scheduler (and --threads if `threads`) on an argparse parser."""
    parser.add_argument("--workers", type=int, default=2,
                        help="LocalCluster workers (default 2; one thread each)")
    parser.add_argument("--scheduler", help="address of an existing Dask scheduler, "
                        "tcp://HOST:PORT, instead of a LocalCluster")
    if threads:
        parser.add_argument("--threads", action="store_true",
                            help="LocalCluster workers as threads of this process")


@contextlib.contextmanager
def cluster_client(scheduler=None, workers=2, threads=False):
    """A dask.distributed Client: of the scheduler at `scheduler`, else of a new LocalCluster of
    `workers` processes with one thread each (`threads`: one process of `workers` threads), its
    worker files in a temporary folder, no dashboard. Closed on exit."""
    from dask.distributed import Client, LocalCluster

    if scheduler:
        with Client(scheduler) as client:
            yield client
        return
    with tempfile.TemporaryDirectory(prefix="ecpsim-dask-") as workspace, \
            LocalCluster(n_workers=1 if threads else workers,
                         threads_per_worker=workers if threads else 1, processes=not threads,
                         dashboard_address=None, local_directory=workspace) as cluster, \
            Client(cluster) as client:
        yield client

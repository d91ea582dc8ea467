"""`ecpsim bench` on a Dask cluster: its shards (`--shard i/N`) as Dask tasks, each running the
ecpsim program in a folder of its own on some worker, their files brought back and joined by
`ecpsim bench --merge` here (docs/benchmarks.md, "Shards"), so the work–precision sweep, the
stability maps and the drop sweep scale out beyond one machine.

    /usr/bin/python3 examples/bench_dask.py -o out/bench [--shards 8] [--workers 2]
        [--scheduler tcp://host:8786] [--ecpsim build/app/ecpsim] [-- ECPSIM_BENCH_OPTIONS…]

Everything after `--` goes to every shard as `ecpsim bench` options (e.g. `--quick`,
`--methods hull,point`); `--no-charts` also goes to the merge. By default a LocalCluster of
--workers processes with one thread each (a shard is one ecpsim process, single-threaded);
--scheduler uses an existing cluster, whose workers must run the same ecpsim build at the path
given by --ecpsim (shards of different builds do not merge: docs/benchmarks.md) and see the
scenes and mesh folders the options name. The workers need no ecpsim Python module.

The shard folders are written to OUT/shards/shard_i/ (each file atomically) and merged into
OUT: work_precision.csv, stability.csv, drop_sweep.csv, drop_failures/, charts and results.md.
A shard that fails stops the sweep with its exit code (1 bad input, 4 internal error) and its
stderr. tests/python/test_bench_dask.py checks that a small sweep merged this way equals the
single-process run.
"""

import argparse
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile

from atomic_output import write_bytes_atomically
from dask_cluster import add_cluster_options, cluster_client

ROOT = pathlib.Path(__file__).resolve().parents[1]
DEFAULT_ECPSIM = ROOT / "build" / "app" / "ecpsim"
STDERR_TAIL = 4000  # characters of a failed shard's stderr kept in the message


class ShardFailed(RuntimeError):
    """An `ecpsim bench --shard` process exited non-zero; carries its exit code."""

    def __init__(self, message, exit_code):
        super().__init__(message, exit_code)  # both in args: it pickles back from a worker
        self.exit_code = exit_code

    def __str__(self):
        return self.args[0]


def run_shard(ecpsim, options, index, count):
    """Runs `ecpsim bench OPTIONS --shard index/count` in a temporary folder on this machine and
    returns its output folder's files as {relative path: bytes}.
    Raises ShardFailed (exit code and stderr) if the program exits non-zero."""
    with tempfile.TemporaryDirectory(prefix=f"ecpsim-shard{index}-") as work:
        out = pathlib.Path(work) / "out"
        command = [str(ecpsim), "bench", *options, "--shard", f"{index}/{count}", "-o", str(out)]
        try:
            done = subprocess.run(command, capture_output=True, text=True, check=False)
        except OSError as error:  # no such program on this worker
            raise ShardFailed(f"shard {index}/{count}: cannot run {ecpsim}: {error}", 1) from None
        if done.returncode != 0:
            raise ShardFailed(f"shard {index}/{count} ({' '.join(command)}) exited with "
                              f"{done.returncode}:\n{done.stderr[-STDERR_TAIL:]}"
                              f"{done.stdout[-STDERR_TAIL:]}", done.returncode)
        return {str(path.relative_to(out)): path.read_bytes()
                for path in sorted(out.rglob("*")) if path.is_file()}


def write_shard(files, folder):
    """A shard's files (run_shard's result) into `folder`, each atomically; what an earlier run
    left there is removed first (the merge reads every CSV it finds)."""
    shutil.rmtree(folder, ignore_errors=True)
    for relative, data in files.items():
        write_bytes_atomically(pathlib.Path(folder) / relative, data)


def merge(ecpsim, shard_folders, out, charts=True):
    """`ecpsim bench --merge` of the folders into `out`; raises ShardFailed if it fails."""
    command = [str(ecpsim), "bench", "--merge", *map(str, shard_folders), "-o", str(out)]
    if not charts:
        command.append("--no-charts")
    done = subprocess.run(command, capture_output=True, text=True, check=False)
    if done.returncode != 0:
        raise ShardFailed(f"merge ({' '.join(command)}) exited with {done.returncode}:\n"
                          f"{done.stderr[-STDERR_TAIL:]}", done.returncode)
    return done.stdout


def run_bench(client, ecpsim, options, shards, out):
    """All `shards` shards of `ecpsim bench OPTIONS` as tasks on the Dask `client`, written to
    OUT/shards/shard_i/ and merged into `out`. Returns the merge's report (stdout)."""
    ecpsim = pathlib.Path(ecpsim).resolve()
    out = pathlib.Path(out)
    # pure=False: a rerun of the same options runs again (the programs may have been rebuilt)
    futures = client.map(run_shard, [ecpsim] * shards, [list(options)] * shards,
                         range(1, shards + 1), [shards] * shards, pure=False)
    folders = [out / "shards" / f"shard_{index}" for index in range(1, shards + 1)]
    for future, folder in zip(futures, folders):
        write_shard(future.result(), folder)
    return merge(ecpsim, folders, out, charts="--no-charts" not in options)


def main(argv=None):
    argv = list(sys.argv[1:] if argv is None else argv)
    options = argv[argv.index("--") + 1:] if "--" in argv else []
    own = argv[:argv.index("--")] if "--" in argv else argv
    parser = argparse.ArgumentParser(
        description=" ".join(__doc__.split("\n\n")[0].split()),
        epilog="Options after -- go to every shard's `ecpsim bench` (e.g. -- --quick).")
    parser.add_argument("-o", "--output", default="out/bench", help="output folder")
    parser.add_argument("--shards", type=int, default=8, help="number of shards (tasks)")
    add_cluster_options(parser)
    parser.add_argument("--ecpsim", default=str(DEFAULT_ECPSIM), help="the ecpsim program")
    args = parser.parse_args(own)
    if args.shards < 1 or args.workers < 1:
        print(f"error: --shards = {args.shards}, --workers = {args.workers}: expected ≥ 1",
              file=sys.stderr)
        return 1
    if not os.access(args.ecpsim, os.X_OK):
        print(f"error: --ecpsim {args.ecpsim}: not an executable program (build it with "
              f"scripts/build.sh)", file=sys.stderr)
        return 1

    with cluster_client(args.scheduler, args.workers) as client:
        try:
            report = run_bench(client, args.ecpsim, options, args.shards, args.output)
        except ShardFailed as failure:
            print(f"error: {failure}", file=sys.stderr)
            return failure.exit_code
    print(report, end="")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""examples/bench_dask.py: `ecpsim bench` shards run as Dask tasks on a LocalCluster and merged
give the single-process run's tables; a failing shard stops it with its exit code."""

import csv
import os
import pathlib
import subprocess

import pytest

import bench_dask
import dask_cluster

BINARY_DIR = pathlib.Path(os.environ.get("ECPSIM_BINARY_DIR", bench_dask.ROOT / "build"))
ECPSIM = BINARY_DIR / "app" / "ecpsim"
# the smallest sweep with rows in every table (tests/app/bench_command_test.cpp's kSmallSweep
# and a drop sweep of one seed of two generated kinds): 8 work-precision rows, 28 stability
# cells, 4 drops
OPTIONS = ["--methods", "hull,point", "--scenarios", "slide,push_slide", "--maps", "impact",
           "--steps", "0.01,0.002", "--drop-kinds", "l_shape,u_shape", "--drop-seeds", "1",
           "--no-charts", "--no-scaling"]
TABLES = {"work_precision.csv": 8, "stability.csv": 28, "drop_sweep.csv": 4}
# columns that time the run (CPU and wall seconds) and so differ between any two runs
TIMING_COLUMNS = {"cpu_per_sim_s", "cpu_s", "wall_s", "max_step_cpu_s"}


def rows_without_timing(path):
    """The table's rows as a sorted list of tuples, its timing columns left out (the merge
    appends shards in shard order, the single run in sweep order)."""
    with open(path, newline="") as file:
        reader = csv.DictReader(file)
        kept = [name for name in reader.fieldnames if name not in TIMING_COLUMNS]
        return sorted(tuple(row[name] for name in kept) for row in reader)


@pytest.fixture(scope="module")
def client():
    # the examples' own LocalCluster: two worker processes of one thread
    with dask_cluster.cluster_client(workers=2) as dask_client:
        yield dask_client


def test_shards_on_the_cluster_merge_into_the_single_run(client, tmp_path):
    single = tmp_path / "single"
    subprocess.run([str(ECPSIM), "bench", *OPTIONS, "-o", str(single)], check=True,
                   capture_output=True)
    report = bench_dask.run_bench(client, ECPSIM, OPTIONS, 3, tmp_path / "dask")
    assert "merged 8 work-precision rows, 28 stability rows and 4 drop rows from 3" in report
    for table, count in TABLES.items():
        merged = rows_without_timing(tmp_path / "dask" / table)
        assert len(merged) == count, table
        assert merged == rows_without_timing(single / table), table
    # every shard ran a part of the sweep in a folder of its own
    for index in (1, 2, 3):
        shard = tmp_path / "dask" / "shards" / f"shard_{index}"
        assert 0 < len(rows_without_timing(shard / "work_precision.csv")) < 8


def test_a_failing_shard_stops_the_sweep_with_its_exit_code(client, tmp_path, capsys):
    with pytest.raises(bench_dask.ShardFailed) as failure:
        bench_dask.run_bench(client, ECPSIM, ["--methods", "nosuch"], 2, tmp_path)
    assert failure.value.exit_code == 1
    assert "--methods 'nosuch': expected one of hull" in str(failure.value)
    assert bench_dask.main(["-o", str(tmp_path), "--ecpsim", str(tmp_path / "none")]) == 1
    assert "not an executable program" in capsys.readouterr().err

"""``--scheduler``: the same jobs on a Dask distributed cluster (a LocalCluster on 127.0.0.1)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from batch_checks import BAD, SCRIPTS, check_output, make_tree, read_manifest

from animstudio.batch import run_batch
from animstudio.errors import ExportError


@pytest.mark.slow
def test_batch_on_a_local_dask_cluster(tmp_path: Path) -> None:
    from distributed import Client, LocalCluster

    inp = make_tree(tmp_path / "in", {**SCRIPTS, **BAD})
    with LocalCluster(
        n_workers=2,
        processes=True,
        threads_per_worker=1,
        host="127.0.0.1",
        dashboard_address=None,
    ) as cluster:
        with Client(cluster.scheduler_address) as client:
            worker_pids = set(client.run(lambda: __import__("os").getpid()).values())
        report = run_batch(
            inp, tmp_path / "dask", formats=("usdc", "bvh"), scheduler=cluster.scheduler_address
        )
    assert report.count("rendered") == len(SCRIPTS) and report.count("failed") == 1
    assert "wlak" in report.failed[0].error and ":2:1:" in report.failed[0].error
    dask_manifest = read_manifest(tmp_path / "dask")
    used = {int(e["worker"].split(":")[1]) for e in dask_manifest.values()}
    assert used <= worker_pids  # every job ran on a cluster worker, none in this process

    # The same batch on the local pool writes byte-identical files.
    run_batch(inp, tmp_path / "local", formats=("usdc", "bvh"), jobs=2)
    local_manifest = read_manifest(tmp_path / "local")
    for rel in SCRIPTS:
        assert dask_manifest[rel]["outputs"] == local_manifest[rel]["outputs"]
        for rec in dask_manifest[rel]["outputs"].values():
            check_output(tmp_path / "dask" / rec["path"])


@pytest.mark.slow  # the client retries for its 10 s connect timeout
def test_unreachable_scheduler_is_a_typed_error(tmp_path: Path) -> None:
    inp = make_tree(tmp_path / "in", SCRIPTS)
    with pytest.raises(
        ExportError, match=re.escape("cannot connect to the Dask scheduler at tcp://127.0.0.1:9")
    ):
        run_batch(inp, tmp_path / "out", scheduler="tcp://127.0.0.1:9")

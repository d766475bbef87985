"""Run a LodForge batch on a Dask cluster: one task per asset (docs/batch.md, "Running on Dask").

    python3 -m lodforge.dask_batch MANIFEST_OR_DIR [--scheduler tcp://host:8786] [batch options]

Every task runs ``lodforge batch SOURCE --only OUTPUT`` on a worker, so an asset is packed by exactly
the code path of ``lodforge batch`` and the packs are byte-identical. The client alone reads and writes
the state file and the report, through ``lodforge batch --plan`` before the tasks and
``lodforge batch --merge`` after them: the formats have one writer, the C++ command.

This module runs the ``lodforge`` executable and never imports the compiled extension, so a worker
needs only ``lodforge`` on its PATH (or ``--lodforge PATH``), Python with ``distributed``, and the
assets, presets and output root at the same paths as the client (shared storage).
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

# The options of `lodforge batch` that choose the assets, their outputs and the state: every call
# (plan, tasks, merge) passes the same ones, so all three see the same assets.
_SELECTION_FLAGS = ("--preset", "--output", "--state")


def _lodforge_command(lodforge, source, options, extra):
    """The argv of ``lodforge batch`` with the options that select assets, state and report."""
    argv = [lodforge, "--quiet", "batch", source]
    for flag in _SELECTION_FLAGS:
        value = options.get(flag)
        if value:
            argv += [flag, value]
    return argv + extra


def run_asset(lodforge, source, options, output, timeout):
    """One task: pack one asset with ``lodforge batch --only`` and return its report record (a dict).

    Runs on a worker. A failed asset is a record with status "failed", not an exception, so one bad
    asset never fails the Dask computation.
    """
    extra = ["--only", output, "--no-state", "--report", "-", "--jobs", "1"]
    if timeout:
        extra += ["--timeout", str(timeout)]
    argv = _lodforge_command(lodforge, source, {k: v for k, v in options.items() if k != "--state"}, extra)
    try:
        done = subprocess.run(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, check=False)
    except OSError as error:
        return _failed_record(output, "cannot run %s on worker: %s" % (lodforge, error))
    try:
        return json.loads(done.stdout)["assets"][0]
    except (ValueError, KeyError, IndexError):
        message = done.stderr.strip().splitlines()[-1] if done.stderr.strip() else "exit status %d" % done.returncode
        return _failed_record(output, message)


def _failed_record(output, message, status="failed"):
    return {"input": "", "preset": "", "output": output, "status": status, "message": message,
            "input_sha256": "", "preset_sha256": "", "lodforge_version": "", "levels": [], "files": [],
            "notes": [], "bytes": 0, "seconds": 0.0}


def _run_lodforge(argv):
    done = subprocess.run(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, check=False)
    if done.returncode != 0:
        sys.stderr.write(done.stderr)
        raise SystemExit(done.returncode)
    return done.stdout


def _parse_args(argv):
    parser = argparse.ArgumentParser(
        prog="python3 -m lodforge.dask_batch",
        description="Run `lodforge batch` on a Dask cluster: one task per asset, the same state file "
                    "and report (docs/batch.md).",
        epilog="Example: python3 -m lodforge.dask_batch /studio/assets.json --scheduler tcp://farm:8786")
    parser.add_argument("source", metavar="SOURCE", help="a manifest (.json, .csv) or a directory of meshes")
    parser.add_argument("--scheduler", help="address of a running Dask scheduler (default: a LocalCluster)")
    parser.add_argument("--workers", type=int, default=None,
                        help="workers of the LocalCluster (default: one per CPU core)")
    parser.add_argument("--lodforge", default=None,
                        help="the lodforge executable, the same path on every worker (default: lodforge on PATH)")
    parser.add_argument("--preset", help="as lodforge batch --preset")
    parser.add_argument("-o", "--output", help="as lodforge batch --output")
    parser.add_argument("--state", help="as lodforge batch --state")
    parser.add_argument("--report", help="as lodforge batch --report")
    parser.add_argument("--timeout", type=float, help="as lodforge batch --timeout (seconds per asset)")
    return parser.parse_args(argv)


def main(argv=None):
    args = _parse_args(sys.argv[1:] if argv is None else argv)
    lodforge = args.lodforge or os.environ.get("LODFORGE") or shutil.which("lodforge")
    if not lodforge:
        sys.stderr.write("lodforge.dask_batch: error: no lodforge executable on PATH; give --lodforge PATH\n")
        return 2
    lodforge = os.path.abspath(lodforge) if os.sep in lodforge else lodforge
    # Absolute paths: the workers' current directories are not the client's.
    options = {"--preset": args.preset, "--output": args.output and os.path.abspath(args.output),
               "--state": args.state and os.path.abspath(args.state)}
    if options["--preset"] and (os.sep in options["--preset"] or options["--preset"].endswith(".json")):
        options["--preset"] = os.path.abspath(options["--preset"])
    source = os.path.abspath(args.source)
    report_flag = ["--report", os.path.abspath(args.report)] if args.report else []

    start = time.monotonic()
    plan = json.loads(_run_lodforge(_lodforge_command(lodforge, source, options, report_flag + ["--plan"])))
    records = [entry["record"] for entry in plan["assets"]]
    todo = [i for i, entry in enumerate(plan["assets"]) if not entry["up_to_date"]]

    from distributed import Client, LocalCluster, as_completed  # imported late: --help without Dask

    cluster = None
    if args.scheduler:
        client = Client(args.scheduler)
    else:
        cluster = LocalCluster(n_workers=args.workers, threads_per_worker=1, dashboard_address=None)
        client = Client(cluster)
    interrupted = False
    jobs = 0
    try:
        jobs = sum(w.get("nthreads", 1) for w in client.scheduler_info()["workers"].values())
        # pure=False: a re-run must pack again even when the arguments are the same.
        futures = {client.submit(run_asset, lodforge, source, options, plan["assets"][i]["output"], args.timeout,
                                 pure=False, key="lodforge-asset-%d-%s" % (i, os.urandom(4).hex())): i
                   for i in todo}
        try:
            for future in as_completed(futures):
                i = futures[future]
                try:
                    records[i] = future.result()
                except Exception as error:  # the task itself broke (a lost worker): the asset failed
                    records[i] = _failed_record(plan["assets"][i]["output"], "Dask task failed: %s" % error)
                records[i]["input"] = records[i]["input"] or plan["assets"][i]["input"]
                records[i]["preset"] = records[i]["preset"] or plan["assets"][i]["preset"]
        except KeyboardInterrupt:
            # Tasks already running finish on their workers (Dask cannot stop them) and write whole packs
            # or nothing (staging directories); those not started are dropped.
            interrupted = True
            client.cancel(list(futures))
    finally:
        client.close()
        if cluster is not None:
            cluster.close()

    for i, entry in enumerate(plan["assets"]):
        if records[i] is None:
            records[i] = _failed_record(entry["output"], "the batch was stopped before this asset finished",
                                        status="cancelled")
            records[i]["input"], records[i]["preset"] = entry["input"], entry["preset"]
    report = {"format": "lodforge-batch-report", "version": 1, "lodforge_version": plan["lodforge_version"],
              "jobs": jobs, "seconds": time.monotonic() - start, "cancelled": interrupted, "assets": records}
    with tempfile.NamedTemporaryFile("w", suffix=".json", prefix="lodforge-dask-", delete=False) as merged:
        json.dump(report, merged)
    try:
        done = subprocess.run(_lodforge_command(lodforge, source, options, report_flag + ["--merge", merged.name]),
                              check=False)
    finally:
        os.unlink(merged.name)
    return 130 if interrupted else done.returncode


if __name__ == "__main__":
    sys.exit(main())

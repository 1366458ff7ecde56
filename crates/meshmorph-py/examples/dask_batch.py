"""A batch of characters on Dask: one source's poses carried to many targets,
one task a target, on a local cluster or on a real one.

    python dask_batch.py batch.toml [more.toml ...]          # a LocalCluster on this machine
    python dask_batch.py batch.toml --workers 4              # ... with four worker processes
    python dask_batch.py batch.toml --scheduler tcp://host:8786   # a running cluster
    python dask_batch.py batch.toml --in-process             # no Dask: the same work in this process

The batch file (TOML or JSON; paths relative to it), as `meshmorph transfer --batch` reads it
(without its `gltf`):

    source = "horse-reference.obj"
    poses = ["horse-01.obj", "horse-02.obj"]

    [[targets]]
    reference = "camel-reference.obj"
    markers = "horse-camel.cons"         # or: correspondence = "horse-camel.corr"
    output = "camel/"                    # one file a pose, named after it, in the target's format

Each task reads its files, fits the correspondence (or loads it), carries every pose and writes
them through meshmorph's output rules, and returns a report: its time, the correspondence's
share of it and the worker's peak memory. On a real cluster the workers must see the files at
the same paths (a shared file system), and meshmorph must be installed on every worker. A target
that fails is reported with its error and the others go on; the exit status says one failed.
"""

import argparse
import json
import os
import resource
import sys
import time

import meshmorph


def read_batch(path):
    """The batch file as a dict, its paths made absolute."""
    with open(path, "rb") as f:
        if path.endswith(".json"):
            batch = json.load(f)
        else:
            import tomllib

            batch = tomllib.load(f)
    here = os.path.dirname(os.path.abspath(path))
    at = lambda p: os.path.normpath(os.path.join(here, p))
    jobs = []
    known = {"reference", "markers", "correspondence", "save_correspondence", "output"}
    for k, t in enumerate(batch.get("targets", [])):
        if not ("markers" in t) ^ ("correspondence" in t):
            raise ValueError("{}: target {} needs markers or a correspondence (one of them)".format(path, k))
        if set(t) - known:
            raise ValueError("{}: target {}: this example does not handle {}".format(path, k, ", ".join(sorted(set(t) - known))))
        markers = t.get("markers")
        markers = [markers] if isinstance(markers, str) else markers
        jobs.append(
            {
                "source": at(batch["source"]),
                "poses": [at(p) for p in batch["poses"]],
                "reference": at(t["reference"]),
                "markers": [at(m) for m in markers] if markers else None,
                "correspondence": at(t["correspondence"]) if "correspondence" in t else None,
                "save_correspondence": at(t["save_correspondence"]) if "save_correspondence" in t else None,
                "output": at(t["output"]),
            }
        )
    return jobs


def peak_memory_mb():
    """This process's peak resident memory so far, in MB (Linux reports KB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def transfer_target(job):
    """One target: the correspondence, every pose carried and written.
    Returns a report; never raises (a failure is reported)."""
    start = time.perf_counter()
    report = {"target": job["reference"], "output": job["output"], "poses": len(job["poses"])}
    try:
        source = meshmorph.read_mesh(job["source"])
        target = meshmorph.read_mesh(job["reference"])
        fit = time.perf_counter()
        if job["correspondence"]:
            c = meshmorph.Correspondence.load(job["correspondence"])
        else:
            c = meshmorph.correspond(
                source.vertices, source.faces, target.vertices, target.faces, meshmorph.read_markers(*job["markers"])
            )
            if job["save_correspondence"]:
                c.save(job["save_correspondence"])
        report["correspondence_s"] = time.perf_counter() - fit
        import numpy as np

        poses = np.stack([meshmorph.read_mesh(p).vertices for p in job["poses"]])
        carried = meshmorph.Transfer(source.vertices, source.faces, target.vertices, target.faces, c).apply_all(poses)
        os.makedirs(job["output"], exist_ok=True)
        ext = os.path.splitext(job["reference"])[1]
        for p, v in zip(job["poses"], carried):
            stem = os.path.splitext(os.path.basename(p))[0]
            meshmorph.write_mesh(os.path.join(job["output"], stem + ext), target, v)
        report["ok"] = True
    except (meshmorph.MeshmorphError, OSError, ValueError) as e:
        report["ok"] = False
        report["error"] = str(e)
    report["seconds"] = time.perf_counter() - start
    report["peak_memory_mb"] = peak_memory_mb()
    return report


def run_in_process(jobs):
    return [transfer_target(j) for j in jobs]


def run_on_dask(jobs, client):
    """One task a target, as many at once as the cluster has room for."""
    futures = client.map(transfer_target, jobs, pure=False)
    return client.gather(futures)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("batch", nargs="+", help="batch files (TOML or JSON), run together")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--scheduler", help="the address of a running Dask scheduler (tcp://host:8786)")
    where.add_argument("--in-process", action="store_true", help="no Dask: every target in this process")
    parser.add_argument("--workers", type=int, default=2, help="worker processes of the local cluster (default 2)")
    args = parser.parse_args()
    jobs = [j for b in args.batch for j in read_batch(b)]
    if args.in_process:
        start = time.perf_counter()
        reports = run_in_process(jobs)
    else:
        from dask.distributed import Client, LocalCluster

        up = time.perf_counter()
        if args.scheduler:
            client = Client(args.scheduler)
        else:
            # One core a worker: meshmorph's own threads (rayon) are held to
            # one in each, so that the workers do not fight over the cores.
            cluster = LocalCluster(
                n_workers=args.workers, threads_per_worker=1, processes=True, env={"RAYON_NUM_THREADS": "1"}
            )
            client = Client(cluster)
        with client:
            client.wait_for_workers(1)
            start = time.perf_counter()
            print("cluster ready in {:.2f} s".format(start - up))
            reports = run_on_dask(jobs, client)
    total = time.perf_counter() - start
    shapes = sum(r["poses"] for r in reports if r["ok"])
    for r in reports:
        if r["ok"]:
            print("{output}: {poses} poses in {seconds:.2f} s ({correspondence_s:.2f} s correspondence), peak {peak_memory_mb:.0f} MB".format(**r))
        else:
            print("{}: FAILED: {}".format(r["target"], r["error"]), file=sys.stderr)
    print("{} shapes in {:.2f} s: {:.1f} shapes a second".format(shapes, total, shapes / total))
    sys.exit(0 if all(r["ok"] for r in reports) else 1)


if __name__ == "__main__":
    main()

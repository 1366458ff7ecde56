"""A batch of characters on Dask: one source's poses carried to many targets,
one task a target, on a local cluster or on a real one.

    python dask_batch.py batch.toml [more.toml ...]          # a LocalCluster on this machine
    python dask_batch.py batch.toml --workers 4              # ... with four worker processes
    python dask_batch.py batch.toml --scheduler tcp://host:8786   # a running cluster
    python dask_batch.py batch.toml --in-process             # no Dask: the same work in this process

The batch file (TOML or JSON; paths relative to it), as `meshmorph transfer --batch` reads it:

    source = "horse-reference.obj"
    poses = ["horse-01.obj", "horse-02.obj"]

    [[targets]]
    reference = "camel-reference.obj"
    markers = "horse-camel.cons"         # or two point files: ["horse.pp", "camel.pp"]
    # correspondence = "horse-camel.corr"  (instead of markers)
    # save_correspondence = "horse-camel.corr"
    output = "camel/"                    # one file a pose, named after it, in the target's format

With glTF and VRM files: a glTF source needs no `poses` (its morph targets are the poses), and a
glTF or VRM target's `gltf` is a copy of its own file with the shapes added as morph targets
(meshmorph.write_gltf), everything else in it kept:

    source = "rig.glb"
    source_mesh = "Face"                 # optional: the mesh's or its node's name
    shapes = ["jawOpen", "eyeBlinkLeft"] # optional: default every one

    [[targets]]
    reference = "mychar.vrm"
    mesh = "Body"                        # optional
    markers = "rig-mychar.txt"           # vertex numbers of the files' meshes as read_gltf gives them
    gltf = "mychar-shapes.vrm"           # never over the reference
    replace_shapes = false               # optional: replace morph targets of the same names
    vrm_expressions = true               # optional: each shape also a VRM custom expression

A glTF mesh is placed in its scene by its node's matrix and welded at seams, as the command line
does it; markers' positions are in that scene. A key this example does not handle (the command
line's `gltf` made from a mesh file that is not glTF, say) is refused, naming it, and so is a
target whose outputs would write over one of its inputs.

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
import numpy as np


GLTF = (".glb", ".gltf", ".vrm")
BATCH_KEYS = {"source", "source_mesh", "poses", "shapes", "targets"}
TARGET_KEYS = {
    "reference", "mesh", "markers", "correspondence", "save_correspondence",
    "gltf", "replace_shapes", "vrm_expressions", "output",
}


def is_gltf(path):
    """Whether `path` names a glTF file (.glb, .gltf or .vrm)."""
    return path.lower().endswith(GLTF)


def read_batch(path):
    """The batch file's targets as jobs, their paths made absolute; a key
    this example does not handle, or keys that do not go together, are
    refused naming the file, the target and the key."""
    with open(path, "rb") as f:
        if path.endswith(".json"):
            batch = json.load(f)
        else:
            import tomllib

            batch = tomllib.load(f)
    here = os.path.dirname(os.path.abspath(path))
    at = lambda p: os.path.normpath(os.path.join(here, p))
    if set(batch) - BATCH_KEYS:
        raise ValueError("{}: this example does not handle {}".format(path, ", ".join(sorted(set(batch) - BATCH_KEYS))))
    if not isinstance(batch.get("source"), str):
        raise ValueError("{}: `source` is the source's file (a path)".format(path))
    source, poses, shapes = batch["source"], batch.get("poses", []), batch.get("shapes", [])
    for key, value in (("poses", poses), ("shapes", shapes)):
        if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
            raise ValueError("{}: `{}` is a list of names, not {!r}".format(path, key, value))
    if not isinstance(batch.get("source_mesh", ""), str):
        raise ValueError("{}: `source_mesh` is a mesh's or node's name, not {!r}".format(path, batch["source_mesh"]))
    if not poses and not is_gltf(source):
        raise ValueError(
            "{} lists no poses (a glTF or VRM source's morph targets would be them; `{}` is not one)".format(path, source)
        )
    if poses and shapes:
        raise ValueError(
            "{}: `shapes` chooses morph targets of a glTF source when no `poses` are listed; give one of them".format(path)
        )
    if "source_mesh" in batch and not is_gltf(source):
        raise ValueError("{}: `source_mesh` chooses the mesh of a glTF or VRM source; `{}` is not one".format(path, source))
    if not batch.get("targets"):
        raise ValueError("{} lists no targets".format(path))
    jobs = []
    for k, t in enumerate(batch["targets"]):
        if not isinstance(t, dict):
            raise ValueError("{}: target {} is not a table of keys".format(path, k))
        named = "target {} of {} ({})".format(k, path, t.get("reference"))
        if set(t) - TARGET_KEYS:
            raise ValueError("{}: this example does not handle {}".format(named, ", ".join(sorted(set(t) - TARGET_KEYS))))
        if not isinstance(t.get("reference"), str):
            raise ValueError("{}: `reference` is the target's file (a path)".format(named))
        if not ("markers" in t) ^ ("correspondence" in t):
            raise ValueError("{}: give `markers` or `correspondence` (one of them)".format(named))
        markers = t.get("markers")
        markers = [markers] if isinstance(markers, str) else markers
        if markers is not None and not 1 <= len(markers) <= 2:
            raise ValueError("{}: `markers` is one file of pairs or two files of points".format(named))
        into_gltf = is_gltf(t["reference"])
        if "output" not in t and "gltf" not in t:
            raise ValueError("{}: give `output` (a folder for the poses), `gltf` or both".format(named))
        if "output" in t and not poses:
            raise ValueError(
                "{}: `output` is a folder for the poses listed in `poses`; a glTF source's morph targets go into `gltf`".format(named)
            )
        if "output" in t and into_gltf:
            raise ValueError("{}: this example writes a glTF or VRM `reference`'s shapes into `gltf` only, not `output`".format(named))
        if "gltf" in t and not into_gltf:
            raise ValueError(
                "{}: this example writes `gltf` as a copy of a glTF or VRM `reference` (meshmorph transfer --batch makes one from other files too)".format(named)
            )
        if not isinstance(t.get("mesh", ""), str):
            raise ValueError("{}: `mesh` is a mesh's or node's name, not {!r}".format(named, t["mesh"]))
        if "mesh" in t and not into_gltf:
            raise ValueError("{}: `mesh` chooses the mesh of a glTF or VRM `reference`".format(named))
        if (t.get("replace_shapes") or t.get("vrm_expressions")) and "gltf" not in t:
            raise ValueError(
                "{}: `replace_shapes` and `vrm_expressions` add to a glTF or VRM `reference`'s own file, written as `gltf`".format(named)
            )
        for flag in ("replace_shapes", "vrm_expressions"):
            if not isinstance(t.get(flag, False), bool):
                raise ValueError("{}: `{}` is true or false, not {!r}".format(named, flag, t[flag]))
        jobs.append(
            {
                "source": at(source),
                "source_mesh": batch.get("source_mesh"),
                "poses": [at(p) for p in poses],
                "shapes": list(shapes),
                "reference": at(t["reference"]),
                "mesh": t.get("mesh"),
                "markers": [at(m) for m in markers] if markers else None,
                "correspondence": at(t["correspondence"]) if "correspondence" in t else None,
                "save_correspondence": at(t["save_correspondence"]) if "save_correspondence" in t else None,
                "output": at(t["output"]) if "output" in t else None,
                "gltf": at(t["gltf"]) if "gltf" in t else None,
                "replace_shapes": t.get("replace_shapes", False),
                "vrm_expressions": t.get("vrm_expressions", False),
            }
        )
        never_over_inputs(jobs[-1], named)
    return jobs


def never_over_inputs(job, named):
    """Refuses a job that would write over one of its inputs (paths
    resolved, links followed), as the command line does."""
    inputs = [job["source"], job["reference"], *job["poses"], *(job["markers"] or []), job["correspondence"]]
    outputs = [job["gltf"], job["save_correspondence"]]
    if job["output"]:
        ext = os.path.splitext(job["reference"])[1]
        outputs += [os.path.join(job["output"], os.path.splitext(os.path.basename(p))[0] + ext) for p in job["poses"]]
    read = {os.path.realpath(p): p for p in inputs if p}
    for out in filter(None, outputs):
        if os.path.realpath(out) in read:
            raise ValueError(
                "{}: the output {} would overwrite the input {}: choose another output path".format(named, out, read[os.path.realpath(out)])
            )


class Reference:
    """A reference mesh as the transfer solves on it: a mesh file's own
    vertices, or a glTF mesh placed in its scene (its node's matrix) with
    the copies of its vertices at seams welded, as `meshmorph transfer`
    does. `file_vertices` are the vertices as the file numbers them (marker
    files and pose files use that numbering)."""

    def __init__(self, path, mesh=None):
        self.path = path
        if is_gltf(path):
            self.gltf = meshmorph.read_gltf(path, mesh)
            self.matrix = self.gltf.transform
            vertices, self.faces, self.index = self.gltf.welded()
            self.vertices = self.placed(vertices)
            self.file_vertices = self.placed(self.gltf.vertices)
            self.file_faces = self.gltf.faces
            # The first copy of each welded vertex, to weld positions given by the file's numbering.
            self.first = np.unique(self.index, return_index=True)[1]
        else:
            self.gltf = None
            self.mesh = meshmorph.read_mesh(path)
            self.vertices = self.file_vertices = self.mesh.vertices
            self.faces = self.file_faces = self.mesh.faces

    def placed(self, v):
        return v @ self.matrix[:3, :3].T + self.matrix[:3, 3]

    def welded(self, v, what):
        """Positions in the file's numbering (placed), on the welded mesh."""
        if len(v) != len(self.file_vertices):
            raise ValueError("{}: {} vertices, {} has {}".format(what, len(v), self.path, len(self.file_vertices)))
        return v if self.gltf is None else v[self.first]

    def unplaced(self, welded):
        """Positions of the welded mesh back in the file's numbering and in
        its mesh's own space, for `meshmorph.write_gltf`."""
        try:
            inverse = np.linalg.inv(self.matrix)
        except np.linalg.LinAlgError:
            raise ValueError("{}: mesh `{}`: its node's matrix cannot be inverted".format(self.path, self.gltf.mesh_name))
        v = welded[self.index]
        return v @ inverse[:3, :3].T + inverse[:3, 3]

    def point(self, side, what):
        """A marker's side (a vertex, a point on a triangle or a position)
        as a position on this reference."""
        if "position" in side:
            return np.asarray(side["position"], dtype=float)
        if "vertex" in side:
            v = side["vertex"]
            if not 0 <= v < len(self.file_vertices):
                raise ValueError("{}: vertex {}, but {} has {} vertices".format(what, v, self.path, len(self.file_vertices)))
            return self.file_vertices[v]
        t = side["triangle"]
        if not 0 <= t < len(self.file_faces):
            raise ValueError("{}: triangle {}, but {} has {} triangles".format(what, t, self.path, len(self.file_faces)))
        return np.asarray(side["barycentric"]) @ self.file_vertices[self.file_faces[t]]


def markers_for(files, source, target):
    """The markers of `files` for the two references: as they are between
    two mesh files; as positions when a glTF mesh is welded, so that they
    land on the welded mesh (correspond puts them on its surface)."""
    markers = meshmorph.read_markers(*files)
    if source.gltf is None and target.gltf is None:
        return markers
    what = " and ".join(files)
    pairs = markers.pairs
    s = np.array([source.point(a, what) for a, _ in pairs])
    t = np.array([target.point(b, what) for _, b in pairs])
    return meshmorph.Markers.from_points(s, t, names=markers.names)


def source_poses(job, source):
    """(names, poses (k, n, 3) on the welded source): the pose files, or a
    glTF source's morph targets (those `shapes` names, else every one)."""
    if job["poses"]:
        names = [os.path.splitext(os.path.basename(p))[0] for p in job["poses"]]
        return names, np.stack([source.welded(meshmorph.read_mesh(p).vertices, p) for p in job["poses"]])
    targets = source.gltf.targets
    if not targets:
        raise ValueError("{}: the mesh `{}` has no morph targets to carry over: give pose files".format(job["source"], source.gltf.mesh_name))
    for name in job["shapes"]:
        if name not in targets:
            raise ValueError(
                "{}: shapes: mesh `{}` has no morph target `{}`; it has {}".format(
                    job["source"], source.gltf.mesh_name, name, ", ".join(targets)
                )
            )
    names = job["shapes"] or list(targets)
    return names, np.stack([source.placed(targets[n])[source.first] for n in names])


def peak_memory_mb():
    """This process's peak resident memory so far, in MB (Linux reports KB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def transfer_target(job):
    """One target: the correspondence, every pose carried and written.
    Returns a report; never raises (a failure is reported)."""
    start = time.perf_counter()
    report = {"target": job["reference"], "output": job["output"] or job["gltf"], "poses": 0}
    try:
        source = Reference(job["source"], job["source_mesh"])
        target = Reference(job["reference"], job["mesh"])
        names, poses = source_poses(job, source)
        report["poses"] = len(names)
        fit = time.perf_counter()
        if job["correspondence"]:
            c = meshmorph.Correspondence.load(job["correspondence"])
        else:
            markers = markers_for(job["markers"], source, target)
            c = meshmorph.correspond(source.vertices, source.faces, target.vertices, target.faces, markers)
            if job["save_correspondence"]:
                c.save(job["save_correspondence"])
        report["correspondence_s"] = time.perf_counter() - fit
        carried = meshmorph.Transfer(source.vertices, source.faces, target.vertices, target.faces, c).apply_all(poses)
        if job["output"]:
            os.makedirs(job["output"], exist_ok=True)
            ext = os.path.splitext(job["reference"])[1]
            for name, v in zip(names, carried):
                meshmorph.write_mesh(os.path.join(job["output"], name + ext), target.mesh, v)
        if job["gltf"]:
            os.makedirs(os.path.dirname(job["gltf"]), exist_ok=True)
            shapes = {name: target.unplaced(v) for name, v in zip(names, carried)}
            meshmorph.write_gltf(
                job["gltf"], target.gltf, shapes, replace=job["replace_shapes"], vrm_expressions=job["vrm_expressions"]
            )
        report["ok"] = True
    except (meshmorph.MeshmorphError, OSError, ValueError) as e:
        report["ok"] = False
        # write_gltf names its own arguments; here they are the batch file's keys.
        report["error"] = str(e).replace("pass replace=True", "set replace_shapes = true")
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

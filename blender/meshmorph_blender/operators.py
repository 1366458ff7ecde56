"""The operators: each checks the selection and its settings, calls the
work in its module, and reports in Blender's report area and status bar
(a sentence saying what to do, never a traceback). The work modules need
numpy and meshmorph, so they are imported once those are loaded: an add-on
whose wheels cannot load still registers and says why.

Every operator runs its work through `_guarded`: the selected meshes are
recorded first, and any error (the add-on's own refusals, and as a last
resort anything unexpected) puts them back as they were and ends in one
sentence in the report, naming the object."""

import os
import threading

import bpy

from . import kept_correspondence, scene_snapshot, wheels
from .refusal import Refusal, sentence


def _meshmorph():
    try:
        return wheels.load()
    except ImportError as e:
        raise Refusal(str(e)) from e


def _settings(context):
    return context.scene.meshmorph


def _source_and_target(context):
    """The two selected meshes: the active one is the target."""
    target = context.active_object
    others = [o for o in context.selected_objects if o != target]
    if (
        target is None
        or target.type != "MESH"
        or not target.select_get()
        or len(others) != 1
        or others[0].type != "MESH"
    ):
        raise Refusal(
            "Select two meshes: first the source (with shape keys), then the target last, so that it is active"
        )
    if others[0].data is target.data:
        raise Refusal("{} and {} share one mesh: select two different meshes".format(others[0].name, target.name))
    _in_object_mode(others[0], target)
    return others[0], target


def _target_of_file(context):
    """The target of a transfer from a Source File: the active mesh, the
    only one selected."""
    target = context.active_object
    if target is None or target.type != "MESH" or not target.select_get():
        raise Refusal("Select the target mesh (made active): the source is the Source File")
    others = [o for o in context.selected_objects if o != target and o.type == "MESH"]
    if others:
        raise Refusal(
            "The source is the Source File, and {} is selected too: select only the target, or clear Source File "
            "to carry {}'s keys".format(others[0].name, others[0].name)
        )
    _in_object_mode(target)
    return target


def _in_object_mode(*objects):
    """Refuses meshes in another mode than Object Mode: in Edit or Sculpt
    Mode their shape keys are not up to date, and Blender would write the
    edit over new keys on leaving it."""
    for obj in objects:
        if obj.mode != "OBJECT":
            raise Refusal("Go back to Object Mode on {} first".format(obj.name))


def _shaped_object(context):
    obj = context.active_object
    if obj is None or obj.type != "MESH" or obj.data.shape_keys is None:
        raise Refusal("Select a mesh with shape keys (made active)")
    _in_object_mode(obj)
    return obj


class _Progress:
    """Blender's progress indicator and status bar for one operator. Calls
    from other threads than Blender's main thread (meshmorph's workers) are
    let pass: Blender's API may only be used from the main thread."""

    def __init__(self, context, title):
        self.wm = context.window_manager
        self.workspace = context.workspace
        self.title = title
        self.wm.progress_begin(0, 1000)

    def __call__(self, stage, done, total):
        if threading.current_thread() is not threading.main_thread():
            return
        self.show(stage, done, total)

    def show(self, stage, done, total):
        self.wm.progress_update(int(1000 * done / max(total, 1)))
        if self.workspace is not None:
            self.workspace.status_text_set("meshmorph: {} {}, {} of {}".format(self.title, stage, done, total))

    def end(self):
        self.wm.progress_end()
        if self.workspace is not None:
            self.workspace.status_text_set(None)


def _unexpected(operator, context, error):
    """The sentence for an error the add-on did not foresee."""
    obj = getattr(context, "active_object", None)
    try:
        on = " on {}".format(obj.name) if obj is not None else ""
    except ReferenceError:
        on = ""
    return "{}{} stopped on an unexpected error ({}: {}); nothing was changed".format(
        operator.bl_label, on, type(error).__name__, error
    )


def _guarded(operator, context, work, objects=None):
    """Runs `work()` and returns its result. On any error the meshes it may
    change (`objects`, else the selected and active ones) are put back as
    they were, the error is reported as one sentence and the result is
    CANCELLED: a traceback never reaches the user."""
    try:
        if objects is None:
            objects = list(context.selected_objects) + [context.active_object]
        snapshot = scene_snapshot.Snapshot(objects)
    except Exception as e:
        operator.report({"ERROR"}, sentence(_unexpected(operator, context, e)))
        return {"CANCELLED"}
    try:
        return work()
    except Refusal as e:
        said = str(e)
    except BaseException as e:  # the last resort: pyo3's PanicException is a BaseException
        if isinstance(e, (SystemExit, GeneratorExit)):
            raise
        said = _unexpected(operator, context, e)
    try:
        snapshot.restore()
    except Exception as e:
        said = "{}; and the meshes could not all be put back ({}: {}), so undo".format(said, type(e).__name__, e)
    operator.report({"ERROR"}, sentence(said))
    return {"CANCELLED"}


class _Refusing:
    """execute() runs `work` guarded (see `_guarded`)."""

    def execute(self, context):
        return _guarded(self, context, lambda: self.work(context))


class MESHMORPH_OT_transfer_shape_keys(_Refusing, bpy.types.Operator):
    """Carry the source's shape keys to the active target mesh (any topology), fitting a correspondence from the markers once"""

    bl_idname = "meshmorph.transfer_shape_keys"
    bl_label = "Transfer Shape Keys"
    bl_options = {"REGISTER", "UNDO"}

    def _gather(self, context):
        """The transfer's arrays, read from Blender (main thread)."""
        s = _settings(context)
        if s.source_file.strip():
            return self._gather_from_file(context, s)
        source, target = _source_and_target(context)
        meshmorph = _meshmorph()
        from . import marker_sources, transfer_keys

        names = transfer_keys.chosen_keys(source, target, s.keys)

        def markers():
            if s.marker_source == "FILE":
                return marker_sources.from_file(meshmorph, source, target, bpy.path.abspath(s.marker_file), bpy.path.abspath(s.target_points_file))
            if s.marker_source == "GROUPS":
                return marker_sources.from_vertex_groups(meshmorph, source, target, s.group_prefix)
            return marker_sources.from_empties(meshmorph, source, target)

        return transfer_keys.Work(meshmorph, source, target, names, markers, s.refit)

    def _gather_from_file(self, context, s):
        """The transfer's arrays with the source read from the Source File
        (a glTF rig): the target is the active mesh, the markers a marker
        file between the file's mesh and the target."""
        target = _target_of_file(context)
        path = bpy.path.abspath(s.source_file.strip())
        if s.marker_source != "FILE":
            raise Refusal(
                "With a Source File, give the markers as a marker file (vertices of {}'s mesh and of {}): "
                "choose Marker File in the meshmorph panel".format(path, target.name)
            )
        if s.target_points_file.strip():
            raise Refusal(
                "With a Source File, give one marker file of pairs between {} and {}, not two point files".format(path, target.name)
            )
        meshmorph = _meshmorph()
        from . import file_source, marker_sources, transfer_keys

        source = file_source.FileSource(meshmorph, path, s.source_mesh)
        names = transfer_keys.chosen_keys(source, target, s.keys)

        def markers():
            marker_file = bpy.path.abspath(s.marker_file)
            read = marker_sources.from_file(meshmorph, source, target, marker_file)
            return file_source.markers(meshmorph, source, target, read, marker_file)

        return transfer_keys.Work(meshmorph, source, target, names, markers, s.refit)

    def _finish(self, job):
        report, reused = job.store()
        how = "with the kept correspondence" if reused else "after a new fit"
        n = len(job.names)
        keys = "1 shape key" if n == 1 else "{} shape keys".format(n)
        self.report({"INFO"}, "{} carried to {} {}. {}".format(keys, job.target.name, how, report))
        return {"FINISHED"}

    def work(self, context):
        """From a script: all at once."""
        job = self._gather(context)
        progress = _Progress(context, "transferring")
        try:
            job.run(progress)
        finally:
            progress.end()
        return self._finish(job)

    def invoke(self, context, event):
        """From the panel: the fit and the solves on a thread of their own
        (meshmorph releases the GIL), Blender's status bar showing how far
        they are; the keys are written once they are done."""
        return _guarded(self, context, lambda: self._start(context))

    def _start(self, context):
        self._job = self._gather(context)
        state = self._state = {"stage": "fit", "done": 0, "total": 1, "error": None, "finished": False}

        def record(stage, done, total):
            state.update(stage=stage, done=done, total=total)

        def run():
            try:
                self._job.run(record)
            except BaseException as e:  # reported from the main thread
                state["error"] = e
            finally:
                state["finished"] = True

        self._progress = _Progress(context, "transferring")
        self._timer = context.window_manager.event_timer_add(0.1, window=context.window)
        threading.Thread(target=run, daemon=True).start()
        context.window_manager.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        if event.type != "TIMER":
            return {"RUNNING_MODAL"}  # the meshes stay as they are until the keys are written
        state = self._state
        self._progress.show(state["stage"], state["done"], state["total"])
        if not state["finished"]:
            return {"RUNNING_MODAL"}
        context.window_manager.event_timer_remove(self._timer)
        self._progress.end()
        error = state["error"]
        if error is not None:
            said = str(error) if isinstance(error, Refusal) else _unexpected(self, context, error)
            self.report({"ERROR"}, sentence(said))
            return {"CANCELLED"}
        return _guarded(self, context, lambda: self._finish(self._job), [self._job.target])


class MESHMORPH_OT_add_inbetweens(_Refusing, bpy.types.Operator):
    """Add as-rigid-as-possible in-between shape keys from one key (or the basis) to another"""

    bl_idname = "meshmorph.add_inbetweens"
    bl_label = "Add In-betweens"
    bl_options = {"REGISTER", "UNDO"}

    def work(self, context):
        obj = _shaped_object(context)
        meshmorph = _meshmorph()
        from . import inbetweens

        s = _settings(context)
        start = s.inbetween_from or obj.data.shape_keys.reference_key.name
        if not s.inbetween_to:
            raise Refusal("Choose the key of {} to go to in the meshmorph panel".format(obj.name))
        names = inbetweens.add(meshmorph, obj, start, s.inbetween_to, s.inbetween_count)
        self.report({"INFO"}, "Added {}".format(", ".join(names)))
        return {"FINISHED"}


class MESHMORPH_OT_bake_animation(_Refusing, bpy.types.Operator):
    """Bake an as-rigid-as-possible animation through the listed keys: one shape key a frame, its value keyframed"""

    bl_idname = "meshmorph.bake_animation"
    bl_label = "Bake ARAP Animation"
    bl_options = {"REGISTER", "UNDO"}

    def work(self, context):
        obj = _shaped_object(context)
        meshmorph = _meshmorph()
        from . import inbetweens

        s = _settings(context)
        keys = [k.strip() for k in s.bake_keys.split(",") if k.strip()]
        names = inbetweens.bake(meshmorph, obj, keys, s.frames_per_key, context.scene.frame_current)
        self.report({"INFO"}, "Baked {} frames from frame {}".format(len(names), context.scene.frame_current))
        return {"FINISHED"}


class MESHMORPH_OT_arkit_expressions(_Refusing, bpy.types.Operator):
    """Put the ARKit expressions (eyeBlinkLeft, jawOpen, ...: the 52 face trackers drive, those the built-in ICT-FaceKit template has) on the active head as shape keys, from 12 or more named landmarks"""

    bl_idname = "meshmorph.arkit_expressions"
    bl_label = "Add ARKit Expressions"
    bl_options = {"REGISTER", "UNDO"}

    def work(self, context):
        obj = context.active_object
        if obj is None or obj.type != "MESH" or not obj.select_get():
            raise Refusal("Select the head (a mesh, made active)")
        _in_object_mode(obj)
        meshmorph = _meshmorph()
        from . import expressions

        s = _settings(context)
        points = expressions.landmarks(
            meshmorph, obj, s.landmark_source, bpy.path.abspath(s.landmark_file), s.group_prefix
        )
        names, missing, warnings = expressions.add(meshmorph, obj, points, s.replace_keys)
        said = "{} shape keys added to {}".format(len(names), obj.name)
        if missing:
            said += "; the template has no {}".format(", ".join(missing))
        for w in warnings:
            self.report({"WARNING"}, sentence(w))
        self.report({"INFO"}, sentence(said))
        return {"FINISHED"}


class MESHMORPH_OT_pick(bpy.types.Operator):
    """Pick marker pairs on the two selected meshes in the browser with meshmorph pick; the saved file becomes the panel's marker file"""

    bl_idname = "meshmorph.pick"
    bl_label = "Pick Markers in the Browser"

    _picking = None
    _timer = None

    def invoke(self, context, event):
        return _guarded(self, context, lambda: self._start(context), [])

    def _start(self, context):
        s = _settings(context)
        try:
            source, target = _source_and_target(context)
            _meshmorph()
            from . import pick

            prefs = context.preferences.addons[__package__].preferences
            command = pick.executable(prefs.executable)
            # Start from the markers given, if any; save to a new file beside
            # them (or beside the .blend), never over an existing one.
            start = [bpy.path.abspath(p) for p in (s.marker_file, s.target_points_file) if p] if s.marker_source == "FILE" else []
            start = [p for p in start if os.path.isfile(p)]
            folder = os.path.dirname(start[0]) if start else (bpy.path.abspath("//") if bpy.data.filepath else bpy.app.tempdir)
            stem = "{}-to-{}.markers".format(bpy.path.clean_name(source.name), bpy.path.clean_name(target.name))
            path = pick.unused_path(folder, stem, ".txt")
            self._picking = pick.Picking(command, source, target, path, start)
        except OSError as e:
            raise Refusal("meshmorph pick could not be started: {}".format(e)) from e
        self._workspace = context.workspace
        self._timer = context.window_manager.event_timer_add(0.5, window=context.window)
        context.window_manager.modal_handler_add(self)
        self.report({"INFO"}, "meshmorph pick is open in the browser; save there, then press Done (Esc here stops it)")
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        try:
            return self._watch(context, event)
        except Exception as e:
            self._picking.stop()
            self.report({"ERROR"}, sentence(_unexpected(self, context, e)))
            return self._end(context, {"CANCELLED"})

    def _watch(self, context, event):
        if event.type == "ESC":
            self._picking.stop()
            return self._end(context, {"CANCELLED"})
        if event.type != "TIMER":
            return {"PASS_THROUGH"}
        s = _settings(context)
        if self._picking.newly_saved():
            s.marker_source, s.marker_file, s.target_points_file = "FILE", self._picking.markers_path, ""
            self.report({"INFO"}, "Markers saved to {}".format(self._picking.markers_path))
        ended = self._picking.finished()
        if ended is None:
            address = self._picking.address()
            if address and self._workspace is not None:
                self._workspace.status_text_set("meshmorph pick at {} (Esc in Blender stops it)".format(address))
            return {"PASS_THROUGH"}
        status, said = ended
        if status != 0:
            self.report({"ERROR"}, sentence("meshmorph pick stopped: {}".format(said.splitlines()[-1] if said else status)))
            return self._end(context, {"CANCELLED"})
        return self._end(context, {"FINISHED"})

    def cancel(self, context):
        """Blender ends the operator (a file opened, the window closed): pick stops too."""
        self._picking.stop()
        self._end(context, {"CANCELLED"})

    def _end(self, context, result):
        context.window_manager.event_timer_remove(self._timer)
        if self._workspace is not None:
            self._workspace.status_text_set(None)
        return result


class MESHMORPH_OT_forget_correspondence(_Refusing, bpy.types.Operator):
    """Forget the correspondence kept on the active object (or whatever it keeps under that name), so that the next transfer fits anew"""

    bl_idname = "meshmorph.forget_correspondence"
    bl_label = "Forget Kept Correspondence"
    bl_options = {"REGISTER", "UNDO"}

    def work(self, context):
        obj = context.active_object
        if obj is None or kept_correspondence.PROPERTY not in obj:
            raise Refusal("Select a target that keeps a correspondence")
        del obj[kept_correspondence.PROPERTY]
        return {"FINISHED"}


CLASSES = (
    MESHMORPH_OT_transfer_shape_keys,
    MESHMORPH_OT_add_inbetweens,
    MESHMORPH_OT_bake_animation,
    MESHMORPH_OT_arkit_expressions,
    MESHMORPH_OT_pick,
    MESHMORPH_OT_forget_correspondence,
)

"""PNG renders of robots, docked pairs and the CuBot bridge: a real z-buffered renderer (VTK,
offscreen), lengths in mm.

Why VTK: the `vtk` wheel (>= 9.4) is already installed with cadquery and renders offscreen
without a display through EGL with Mesa's software rasteriser (Debian ``libegl1``,
``libegl-mesa0``, ``libgl1-mesa-dri``); where ``DISPLAY`` is unset the EGL window is chosen
(``VTK_DEFAULT_OPENGL_WINDOW=vtkEGLRenderWindow``, set before the first window is made, unless
the caller set it). Hidden surfaces are resolved per pixel by the depth buffer, so a part in
front always occludes one behind, whatever order the parts are given in (the matplotlib
renderer this replaces sorted whole polygons and got that wrong).

Printed parts are coloured by role (:data:`cubot_cad.robots.base.ROLE_COLOURS`: pins orange, latch
blades blue, rails green, keys purple, body grey) so every connector stands out; renders are
:data:`DEFAULT_SIZE_PX` (1600 x 1200) unless asked otherwise. Views are orthographic (true
proportions, framed tightly on the model), the camera placed by elevation and azimuth in
degrees as matplotlib's ``view_init`` places it.

Public API: :func:`render_robot`, :func:`render_pair`, :func:`render_bridge` (what the CLI
calls), :func:`render_shapes` (groups of shapes to a PNG) and :func:`render_image` (the same
to an RGB array, for tests and composites).
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from cubot_cad.atomic import write_via

#: Colours (rgb 0-1) of the pair renders' two robots and of bought-part stand-ins' dark parts.
PRINTED = (0.86, 0.86, 0.80)
SECOND = (0.55, 0.70, 0.90)
BACKGROUND = (1.0, 1.0, 1.0)
#: Width x height of every render unless asked otherwise (pixels).
DEFAULT_SIZE_PX = (1600, 1200)
#: Tessellation of rendered shapes: linear (mm) and angular (rad) tolerance.
RENDER_TOLERANCE_MM = 0.1
RENDER_ANGULAR_RAD = 0.3


@dataclass(frozen=True)
class Label:
    """A numbered callout: ``text`` in a box joined by a leader line to ``point_mm`` (a 3D point in
    the model frame, mm); the box goes where it covers least of the model and no other box."""

    text: str
    point_mm: tuple[float, float, float]


def _tris(shape, tol: float = RENDER_TOLERANCE_MM, angular: float = RENDER_ANGULAR_RAD) -> np.ndarray:
    """Triangles (n, 3, 3) in mm of an OCC shape (an (n, 3, 3) array passes through)."""
    if isinstance(shape, np.ndarray):
        return shape.reshape(-1, 3, 3)
    verts, tris = shape.tessellate(tol, angular)
    if not tris:
        return np.zeros((0, 3, 3))
    v = np.array([(p.x, p.y, p.z) for p in verts], dtype=float)
    return v[np.array(tris, dtype=np.int64)]


def _indexed(shape, tol: float, angular: float) -> tuple[np.ndarray, np.ndarray]:
    """(vertices (m, 3) mm, faces (n, 3) int) of an OCC shape or an (n, 3, 3) triangle array."""
    if isinstance(shape, np.ndarray):  # weld shared corners (to 1e-6 mm): edges and normals need neighbours
        t = shape.reshape(-1, 3, 3)
        if len(t) == 0:
            return np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)
        v, inv = np.unique(np.round(t.reshape(-1, 3), 6), axis=0, return_inverse=True)
        return v, inv.reshape(-1, 3).astype(np.int64)
    verts, tris = shape.tessellate(tol, angular)
    if not tris:
        return np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)
    return np.array([(p.x, p.y, p.z) for p in verts], dtype=float), np.array(tris, dtype=np.int64)


def _vtk():
    """Import the VTK modules the renderer needs, choosing the headless EGL window without a display."""
    if not os.environ.get("DISPLAY") and not os.environ.get("WAYLAND_DISPLAY"):
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    try:
        import vtkmodules.vtkRenderingFreeType  # noqa: F401  (text actors)
        import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (the OpenGL back end's factories)
        from vtkmodules import (
            vtkCommonCore,
            vtkCommonDataModel,
            vtkFiltersCore,
            vtkRenderingCore,
        )
        from vtkmodules.util.numpy_support import (
            numpy_to_vtk,
            numpy_to_vtkIdTypeArray,
            vtk_to_numpy,
        )
    except ImportError as exc:  # pragma: no cover - vtk comes with cadquery
        raise RuntimeError("rendering needs the vtk wheel (pip install 'vtk>=9.4', part of voidcross[cad])") from exc
    return dict(core=vtkCommonCore, dm=vtkCommonDataModel, filters=vtkFiltersCore, rc=vtkRenderingCore,
                numpy_to_vtk=numpy_to_vtk, ids=numpy_to_vtkIdTypeArray, vtk_to_numpy=vtk_to_numpy)


def _polydata(V, verts: np.ndarray, faces: np.ndarray):
    pts = V["core"].vtkPoints()
    pts.SetData(V["numpy_to_vtk"](np.ascontiguousarray(verts, dtype=np.float64), deep=True))
    cells = V["dm"].vtkCellArray()
    offsets = np.arange(0, 3 * len(faces) + 1, 3, dtype=np.int64)
    cells.SetData(V["ids"](offsets, deep=True), V["ids"](np.ascontiguousarray(faces.ravel(), dtype=np.int64), deep=True))
    pd = V["dm"].vtkPolyData()
    pd.SetPoints(pts)
    pd.SetPolys(cells)
    return pd


def camera_axes(elev_deg: float, azim_deg: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(direction from the model to the eye, screen right, screen up), unit vectors, for a camera at
    ``elev_deg`` above the xy plane and ``azim_deg`` about z from +x (matplotlib's ``view_init``)."""
    e, a = math.radians(elev_deg), math.radians(azim_deg)
    eye = np.array([math.cos(e) * math.cos(a), math.cos(e) * math.sin(a), math.sin(e)])
    right = np.cross([0.0, 0.0, 1.0], eye)
    if np.linalg.norm(right) < 1e-9:  # looking straight down or up: +x is screen up
        right = np.cross([1.0, 0.0, 0.0], eye)
    right /= np.linalg.norm(right)
    up = np.cross(eye, right)
    return eye, right, up


def render_image(groups, title: str = "", elev: float = 22, azim: float = -58,
                 size_px: tuple[int, int] = DEFAULT_SIZE_PX, shading: str = "lit", edges: bool = True,
                 labels: list[Label] | tuple = (), tolerance_mm: float = RENDER_TOLERANCE_MM,
                 angular_rad: float = RENDER_ANGULAR_RAD, margin: float = 0.04,
                 supersample: int = 2) -> np.ndarray:
    """Render ``groups`` (list of (shapes, rgb 0-1); a shape is an OCC shape or an (n, 3, 3) array of
    triangles in mm) and return the image as a (height, width, 3) uint8 array, top row first.

    ``shading``: ``"lit"`` (three lights round the camera, the documentation look) or ``"flat"`` (every
    pixel exactly its part's colour: what the tests count). ``edges`` draws feature edges (> 35 deg)
    dark, so stacked plates and pins read apart. ``labels`` are numbered callouts. The view is
    orthographic and framed on the model's silhouette with ``margin`` (fraction of the frame) round it.
    Lit renders are drawn at ``supersample`` times the size and box-filtered down (anti-aliasing:
    VTK's FXAA pass gives black frames on Mesa's EGL here); flat ones are not, so that their pixels
    keep the exact colours."""
    V = _vtk()
    rc = V["rc"]
    ss = 1 if shading == "flat" else max(1, int(supersample))
    W, H = int(size_px[0]) * ss, int(size_px[1]) * ss
    eye, right, up = camera_axes(elev, azim)
    ren = rc.vtkRenderer()
    ren.SetBackground(*BACKGROUND)
    lo_r = lo_u = math.inf
    hi_r = hi_u = -math.inf
    lo, hi = np.full(3, np.inf), np.full(3, -np.inf)
    for shapes, rgb in groups:
        for s in shapes:
            verts, faces = _indexed(s, tolerance_mm, angular_rad)
            if len(faces) == 0:
                continue
            lo, hi = np.minimum(lo, verts.min(axis=0)), np.maximum(hi, verts.max(axis=0))
            pr, pu = verts @ right, verts @ up
            lo_r, hi_r = min(lo_r, pr.min()), max(hi_r, pr.max())
            lo_u, hi_u = min(lo_u, pu.min()), max(hi_u, pu.max())
            pd = _polydata(V, verts, faces)
            mapper = rc.vtkPolyDataMapper()
            if shading == "lit":
                nf = V["filters"].vtkPolyDataNormals()
                nf.SetInputData(pd)
                nf.SetFeatureAngle(35.0)
                nf.SplittingOn()
                nf.ConsistencyOn()
                nf.AutoOrientNormalsOff()
                mapper.SetInputConnection(nf.GetOutputPort())
            else:
                mapper.SetInputData(pd)
            actor = rc.vtkActor()
            actor.SetMapper(mapper)
            prop = actor.GetProperty()
            prop.SetColor(*rgb)
            if shading == "lit":
                prop.SetAmbient(0.25)
                prop.SetDiffuse(0.75)
                prop.SetSpecular(0.15)
                prop.SetSpecularPower(20)
                prop.BackfaceCullingOff()
            else:
                prop.LightingOff()
                prop.SetAmbient(1.0)
                prop.SetDiffuse(0.0)
            # push the surfaces back a little so their edges are drawn on top of them
            mapper.SetResolveCoincidentTopologyToPolygonOffset()
            ren.AddActor(actor)
            if edges and shading == "lit":
                fe = V["filters"].vtkFeatureEdges()
                fe.SetInputData(pd)
                fe.BoundaryEdgesOn()
                fe.FeatureEdgesOn()
                fe.SetFeatureAngle(35.0)
                fe.NonManifoldEdgesOff()
                fe.ManifoldEdgesOff()
                fe.ColoringOff()
                em = rc.vtkPolyDataMapper()
                em.SetInputConnection(fe.GetOutputPort())
                ea = rc.vtkActor()
                ea.SetMapper(em)
                ea.GetProperty().SetColor(*(0.35 * np.asarray(rgb)))
                ea.GetProperty().LightingOff()
                ea.GetProperty().SetLineWidth(1.2 * ss)
                ren.AddActor(ea)
    if not math.isfinite(lo_r):
        raise ValueError("nothing to render: every shape is empty")
    # the framing includes the labelled points
    for lab in labels:
        p = np.asarray(lab.point_mm, dtype=float)
        pr, pu = float(p @ right), float(p @ up)
        lo_r, hi_r, lo_u, hi_u = min(lo_r, pr), max(hi_r, pr), min(lo_u, pu), max(hi_u, pu)
    centre_ru = np.array([(lo_r + hi_r) / 2, (lo_u + hi_u) / 2])
    half_w, half_h = (hi_r - lo_r) / 2, (hi_u - lo_u) / 2
    aspect = W / H
    scale = max(half_h, half_w / aspect) * (1 + 2 * margin) + (0.06 * max(half_h, half_w / aspect) if title else 0)
    mid = (lo + hi) / 2
    # focal point: the model centre moved in the screen plane to the silhouette's centre
    focal = mid + right * (centre_ru[0] - mid @ right) + up * (centre_ru[1] - mid @ up)
    dist = float(np.linalg.norm(hi - lo)) * 2 + 100.0
    cam = ren.GetActiveCamera()
    cam.ParallelProjectionOn()
    cam.SetFocalPoint(*focal)
    cam.SetPosition(*(focal + eye * dist))
    cam.SetViewUp(*up)
    cam.SetParallelScale(scale)
    ren.ResetCameraClippingRange()
    cr = cam.GetClippingRange()
    cam.SetClippingRange(max(1e-3, cr[0] * 0.5), cr[1] * 2)
    if shading == "lit":
        ren.RemoveAllLights()
        for pos, intensity in ((eye + 0.6 * right + 0.8 * up, 0.75), (eye - 0.8 * right + 0.2 * up, 0.35),
                               (eye - 0.3 * up, 0.2)):
            light = rc.vtkLight()
            light.SetLightTypeToSceneLight()
            light.SetPosition(*(focal + pos * dist))
            light.SetFocalPoint(*focal)
            light.SetIntensity(intensity)
            ren.AddLight(light)
    rw = rc.vtkRenderWindow()
    rw.SetOffScreenRendering(1)
    rw.SetSize(W, H)
    rw.AddRenderer(ren)
    try:
        rw.Render()
        grab = rc.vtkWindowToImageFilter()
        grab.SetInput(rw)
        grab.SetInputBufferTypeToRGB()
        grab.ReadFrontBufferOff()
        grab.Update()
        img = grab.GetOutput()
        w, h, _ = img.GetDimensions()
        arr = V["vtk_to_numpy"](img.GetPointData().GetScalars()).reshape(h, w, -1)[::-1, :, :3].copy()
    finally:
        rw.Finalize()
    if arr.shape[:2] != (H, W):
        raise RuntimeError(f"offscreen render returned {arr.shape[1]} x {arr.shape[0]} px, asked for {W} x {H}")
    if ss > 1:  # box-filter the supersampled frame down: the anti-aliasing
        arr = arr.reshape(H // ss, ss, W // ss, ss, 3).mean(axis=(1, 3)).round().astype(np.uint8)
        W, H = W // ss, H // ss
    if title or labels:
        def to_px(p):
            d = np.asarray(p, dtype=float) - focal
            return (W / 2 + (d @ right) / scale * (H / 2), H / 2 - (d @ up) / scale * (H / 2))

        arr = _annotate(arr, title, [(lab.text, to_px(lab.point_mm)) for lab in labels])
    return arr


def _font(size_px: int):
    from PIL import ImageFont

    try:
        return ImageFont.load_default(size=size_px)
    except TypeError:  # pragma: no cover - Pillow < 10.1
        return ImageFont.load_default()


def _segments_cross(p1, p2, q1, q2) -> bool:
    """Whether the segments p1-p2 and q1-q2 (pixels) cross at a point inside both."""
    def orient(a, b, c):
        return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])

    d1, d2 = orient(q1, q2, p1), orient(q1, q2, p2)
    d3, d4 = orient(p1, p2, q1), orient(p1, p2, q2)
    return d1 * d2 < 0 and d3 * d4 < 0


def _annotate(arr: np.ndarray, title: str, labels: list[tuple[str, tuple[float, float]]]) -> np.ndarray:
    """Draw the title (top centre) and numbered callouts (a boxed number joined to its pixel by a
    leader line, placed where it overlaps no other callout and as little of the model as can be)."""
    from PIL import Image, ImageDraw

    H, W = arr.shape[:2]
    bg = np.all(arr >= 250, axis=2)
    im = Image.fromarray(arr, "RGB")
    dr = ImageDraw.Draw(im)
    if title:
        f = _font(max(16, H // 42))
        dr.text((W / 2, 10), title, fill=(20, 20, 20), font=f, anchor="ma")
    f = _font(max(16, H // 40))
    placed: list[tuple[float, float, float, float]] = []
    kept: list[tuple[str, float, float, float, float]] = []
    cx, cy = W / 2, H / 2
    for text, (px, py) in labels:
        x0, y0, x1, y1 = dr.textbbox((0, 0), text, font=f)
        bw, bh = x1 - x0 + 12, y1 - y0 + 10
        away = math.atan2(py - cy, px - cx)
        best = None
        for dist in (60, 90, 130, 180, 240, 310):
            for k in range(16):  # straight away from the centre first, then turning both ways
                ang = away + (k + 1) // 2 * (1 if k % 2 else -1) * math.pi / 8
                bx, by = px + dist * math.cos(ang) - bw / 2, py + dist * math.sin(ang) - bh / 2
                if bx < 2 or by < 40 or bx + bw > W - 2 or by + bh > H - 2:
                    continue
                if any(bx < q[2] + 4 and q[0] < bx + bw + 4 and by < q[3] + 4 and q[1] < by + bh + 4 for q in placed):
                    continue
                cover = float(1.0 - bg[int(by):int(by + bh), int(bx):int(bx + bw)].mean())
                score = cover * 2 + dist / 310
                if best is None or score < best[0]:
                    best = (score, bx, by)
            if best is not None and best[0] < 0.5:
                break
        if best is None:
            continue  # no room: leave it out rather than hide another callout
        _, bx, by = best
        placed.append((bx, by, bx + bw, by + bh))
        kept.append((text, px, py, bw, bh))
    # swap the boxes of two callouts whose leader lines cross (a few passes settle it)
    centres = [((q[0] + q[2]) / 2, (q[1] + q[3]) / 2) for q in placed]
    for _ in range(4):
        swapped = False
        for i in range(len(kept)):
            for j in range(i + 1, len(kept)):
                a0, a1 = kept[i][1:3], centres[i]
                b0, b1 = kept[j][1:3], centres[j]
                if _segments_cross(a0, a1, b0, b1):
                    centres[i], centres[j] = centres[j], centres[i]
                    swapped = True
        if not swapped:
            break
    boxes = [(mx - bw / 2, my - bh / 2, mx + bw / 2, my + bh / 2)
             for (_t, _x, _y, bw, bh), (mx, my) in zip(kept, centres, strict=True)]
    for (_t, px, py, _w, _h), box in zip(kept, boxes, strict=True):  # leaders first, boxes over them
        ex = min(max(px, box[0]), box[2])
        ey = min(max(py, box[1]), box[3])
        dr.line([(px, py), (ex, ey)], fill=(30, 30, 30), width=2)
        dr.ellipse([px - 4, py - 4, px + 4, py + 4], fill=(30, 30, 30))
    for (text, _x, _y, _w, _h), box in zip(kept, boxes, strict=True):
        dr.rectangle(box, fill=(255, 255, 215), outline=(30, 30, 30), width=2)
        dr.text(((box[0] + box[2]) / 2, (box[1] + box[3]) / 2), text, fill=(10, 10, 10), font=f, anchor="mm")
    return np.asarray(im).copy()


def write_png(path: str | os.PathLike, img: np.ndarray) -> Path:
    """Write an (h, w, 3) uint8 image as PNG, atomically."""
    from PIL import Image

    p = Path(path)
    write_via(p, lambda tmp: Image.fromarray(np.ascontiguousarray(img, dtype=np.uint8), "RGB").save(tmp, format="PNG"))
    return p


def render_shapes(groups, path: str | os.PathLike, title: str, elev: float = 22, azim: float = -58,
                  size_in: float | None = None, size_px: tuple[int, int] = DEFAULT_SIZE_PX, **kw) -> Path:
    """``groups``: list of (shapes, rgb); a shape may also be an (n, 3, 3) array of triangles (mm).
    Writes a ``size_px`` PNG atomically and returns its path. ``size_in`` (the old figure width in
    inches) is accepted and ignored: renders are sized in pixels. Other keywords go to
    :func:`render_image`."""
    del size_in
    return write_png(path, render_image(groups, title, elev, azim, size_px, **kw))


def robot_groups(robot, placed: list | None = None, component_roles=("wheel", "caster", "motor", "power")):
    """Render groups of a robot: each printed part in its role colour, chosen stand-ins in theirs."""
    from cubot_cad.robots.base import role_colour

    groups = [([p.shape], role_colour(p.role)) for p in (robot.placed if placed is None else placed)]
    for comp in robot.components():
        if comp.role in component_roles:
            groups.append((comp.solids(), tuple(comp.colour)))
    return groups


def render_robot(robot, path, size_px: tuple[int, int] = DEFAULT_SIZE_PX) -> Path:
    """The assembled robot, connectors in their role colours, at ``size_px`` (default 1600 x 1200)."""
    mp = robot.mass_properties()
    title = f"{robot.title}: {mp.printed_mass_kg * 1e3:.0f} g printed (solid model), {mp.mass_kg * 1e3:.0f} g total"
    return render_shapes(robot_groups(robot), path, title, size_px=size_px)


def render_pair(pair, path, size_px: tuple[int, int] = DEFAULT_SIZE_PX) -> Path:
    """A docked pair: robot A grey, robot B blue."""
    title = f"{pair.name}: gap {pair.gap_mm:.2f} mm, interference {pair.interference_mm3:.3f} mm^3"
    return render_shapes([(pair.shapes_a, PRINTED), (pair.shapes_b, SECOND)], path, title, size_px=size_px)


#: Printed parts shown in the bridge render (the others are inside the bodies).
BRIDGE_RENDER_ROLES = ("body", "cover", "rail", "pin", "blade", "cross_key")


def render_bridge(robot, pair, path, size_px: tuple[int, int] = (2400, 1200)) -> Path:
    """The bridge of :mod:`cubot_cad.outputs.gltf` (five docked CuBots across a void between two slabs).
    One robot is tessellated once and its triangles translated."""
    from cubot_cad.outputs.gltf import SLAB_COLOUR, bridge_layout
    from cubot_cad.robots.base import role_colour
    from cubot_cad.shapes import box

    lay = bridge_layout(robot, pair)
    by_role: dict[str, list] = {}
    for p in robot.build_placed(blades_locked=True):
        if p.role in BRIDGE_RENDER_ROLES:
            by_role.setdefault(p.role, []).append(_tris(p.shape.copy(False), 0.3, 0.5))
    printed = {r: np.concatenate(t) for r, t in by_role.items()}
    comps = np.concatenate([_tris(s, 0.3, 0.5) for c in robot.components() if c.role in ("wheel", "caster")
                            for s in c.solids()])
    groups = []
    for i, o in enumerate(lay.offsets_mm):
        o = np.asarray(o, dtype=float)
        for role, t in printed.items():
            rgb = role_colour(role) if role != "body" else (PRINTED if i % 2 == 0 else SECOND)
            groups.append(([t + o], rgb))
        groups.append(([comps + o], (0.25, 0.25, 0.25)))
    groups.append(([box(*s) for s in lay.slabs_mm], SLAB_COLOUR))
    title = (f"bridge: {len(lay.offsets_mm)} CuBots docked front to rear (pitch {lay.pitch_mm:.1f} mm) "
             f"across a {lay.void_mm:.0f} mm void")
    return render_shapes(groups, path, title, elev=18, azim=-70, size_px=size_px)

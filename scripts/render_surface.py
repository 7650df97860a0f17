#!/usr/bin/env python3
"""Render a vascsim vessel-wall surface (.vtu, or one frame of a .pvd series) to a shaded 3-D PNG.

Usage: /usr/bin/python3 scripts/render_surface.py INPUT(.vtu|.pvd) --out PNG [options]

The surface is a VTK UnstructuredGrid of triangles (positions in m, deformed) with point data
'displacement' (m) and 'normal', and optionally cell data 'outer' (1 on the outer wall, 0 on the
inner wall). Faces are shaded with a Blinn-Phong model (ambient + Lambert diffuse + specular) from
smoothed face normals and a key light placed above-left of the camera, and drawn with matplotlib's
mplot3d at equal aspect on all axes, in mm.

A run's tools (the catheter) are drawn in grey from vtk/tools.pvd next to the surface series when the run wrote
one; the title is the scene's name from the run's summary.json. --all-frames renders every frame of a .pvd
into a folder (frame_NNNN.png) and an animated GIF (animation.gif, matplotlib's Pillow writer).

Examples:
  render_surface.py out/vein/vtk/surface.pvd --out docs/img/vein.png
  render_surface.py out/catheter/vtk/surface.pvd --all-frames --color displacement --out out/catheter/frames
  render_surface.py out/vein/vtk/surface.pvd --frame 3 --color displacement --out dent.png
  render_surface.py out/vein/vtk/surface_0010.vtu --nodes out/vein/vtk/nodes_0010.vtu --out nodes.png

Errors (missing or unreadable file, no triangle cells, bad frame index) print one line on stderr
and exit with code 2.
"""
import argparse
import json
import os
import sys
import time
import xml.etree.ElementTree as ET

import numpy as np

PROG = "render_surface"
INNER_DIM = 0.75  # inner wall (lumen side) is drawn a little darker
NODE_RGB = (0.10, 0.20, 0.45)
TOOL_RGB = (0.62, 0.64, 0.68)  # the catheter: steel grey


class RenderError(Exception):
    """A user-facing error: one line, exit code 2."""


# ----------------------------------------------------------------------------------------- input
def read_pvd(path):
    """[(timestep, absolute file path)] in file order."""
    try:
        root = ET.parse(path).getroot()
    except (ET.ParseError, OSError) as e:
        raise RenderError(f"{path}: cannot parse .pvd: {e}")
    base = os.path.dirname(os.path.abspath(path))
    entries = []
    for ds in root.iter("DataSet"):
        f = ds.get("file")
        if not f:
            continue
        try:
            t = float(ds.get("timestep", "nan"))
        except ValueError:
            t = float("nan")
        entries.append((t, f if os.path.isabs(f) else os.path.join(base, f)))
    if not entries:
        raise RenderError(f"{path}: .pvd collection has no <DataSet file=...> entries")
    return entries


def resolve_input(path, frame):
    """Returns (vtu path, description of the frame or None)."""
    if not os.path.isfile(path):
        raise RenderError(f"{path}: not found")
    if not path.lower().endswith(".pvd"):
        return path, None
    entries = read_pvd(path)
    n = len(entries)
    i = n - 1 if frame is None else frame
    if not -n <= i < n:
        raise RenderError(f"{path}: frame {frame} out of range (collection has {n} frames: 0..{n - 1})")
    i %= n
    t, f = entries[i]
    if not os.path.isfile(f):
        raise RenderError(f"{f}: not found (frame {i} of {path})")
    # The .pvd timestep is a time (dynamic models) or a load factor (quasi-static): no unit implied.
    return f, f"frame {i} of 0..{n - 1}, timestep {t:g}"


def read_mesh(path):
    import meshio

    if not os.path.isfile(path):
        raise RenderError(f"{path}: not found")
    try:
        # the format's reader itself: meshio.read() would print to stdout and sys.exit(1) on failure
        return meshio.vtu.read(path)
    except (Exception, SystemExit) as e:  # ReadError, ValueError, KeyError, ParseError, ...
        msg = str(e).strip().splitlines()[0] if str(e).strip() else "not a VTK XML UnstructuredGrid file"
        raise RenderError(f"{path}: cannot read as .vtu ({type(e).__name__}): {msg}")


def load_surface(path, outer_only):
    """Returns dict with pts (N,3) m, tri (M,3), disp (N,3) m or None, normal (N,3) or None,
    outer (M,) or None."""
    m = read_mesh(path)
    pts = np.asarray(m.points, dtype=float)
    if pts.ndim != 2 or pts.shape[0] == 0:
        raise RenderError(f"{path}: no points")
    if pts.shape[1] == 2:
        pts = np.column_stack([pts, np.zeros(len(pts))])
    tris, outers = [], []
    have_outer = "outer" in m.cell_data
    for bi, block in enumerate(m.cells):
        if block.type != "triangle":
            continue
        tris.append(np.asarray(block.data, dtype=np.int64))
        if have_outer:
            outers.append(np.asarray(m.cell_data["outer"][bi]).reshape(-1))
    if not tris:
        types = sorted({b.type for b in m.cells}) or ["none"]
        raise RenderError(f"{path}: no triangle cells (cell types: {', '.join(types)})")
    tri = np.concatenate(tris)
    outer = np.concatenate(outers) if have_outer else None
    if tri.min() < 0 or tri.max() >= len(pts):
        raise RenderError(f"{path}: triangle connectivity out of range")

    def vec(name, ncomp):
        a = m.point_data.get(name)
        if a is None:
            return None
        a = np.asarray(a, dtype=float)
        return a if a.shape == (len(pts), ncomp) else None

    disp, normal = vec("displacement", 3), vec("normal", 3)

    if outer_only:
        if outer is None:
            print(f"{PROG}: {path}: no cell data 'outer'; --outer-only ignored", file=sys.stderr)
        elif not np.any(outer == 1):
            print(f"{PROG}: {path}: no triangles with outer == 1; --outer-only ignored", file=sys.stderr)
        else:
            keep = outer == 1
            tri, outer = tri[keep], outer[keep]

    # drop triangles with non-finite vertices (a diverged run should still render what is left)
    ok = np.all(np.isfinite(pts[tri]).reshape(len(tri), -1), axis=1)
    if not ok.all():
        print(f"{PROG}: {path}: skipping {np.count_nonzero(~ok)} triangles with non-finite points", file=sys.stderr)
        tri = tri[ok]
        outer = outer[ok] if outer is not None else None
        if len(tri) == 0:
            raise RenderError(f"{path}: all triangles have non-finite points")
    return {"pts": pts, "tri": tri, "disp": disp, "normal": normal, "outer": outer}


def load_nodes(path, frame):
    vtu, _ = resolve_input(path, frame)
    pts = np.asarray(read_mesh(vtu).points, dtype=float)
    if pts.ndim != 2 or len(pts) == 0:
        raise RenderError(f"{vtu}: no points")
    if pts.shape[1] == 2:
        pts = np.column_stack([pts, np.zeros(len(pts))])
    return pts[np.all(np.isfinite(pts), axis=1)]


# -------------------------------------------------------------------------------------- shading
def _normalize(v):
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    return v / np.where(n > 0, n, 1.0)


def camera_frame(elev_deg, azim_deg):
    """Unit vectors (to_eye, screen_right, screen_up) of matplotlib's 3-D camera (z up)."""
    e, a = np.radians(elev_deg), np.radians(azim_deg)
    to_eye = np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])
    right = np.array([-np.sin(a), np.cos(a), 0.0])
    up = np.cross(to_eye, right)
    return to_eye, right, up


def face_shading_normals(pts, tri, point_normal=None):
    """Smoothed per-face normals: area-weighted vertex normals averaged over each face's corners.

    Face orientation is made consistent with the stored point 'normal' if present (the winding of
    the writer is not relied upon); otherwise the winding is trusted.
    """
    p0, p1, p2 = pts[tri[:, 0]], pts[tri[:, 1]], pts[tri[:, 2]]
    fn = np.cross(p1 - p0, p2 - p0)  # |fn| = 2 * area
    if point_normal is not None:
        ref = point_normal[tri].sum(axis=1)
        fn *= np.where(np.einsum("ij,ij->i", fn, ref) < 0, -1.0, 1.0)[:, None]
    n = len(pts)
    vn = np.zeros((n, 3))
    flat = tri.reshape(-1)
    for k in range(3):  # loop over 3 components, vectorised over triangles
        vn[:, k] = np.bincount(flat, weights=np.repeat(fn[:, k], 3), minlength=n)
    vn = _normalize(vn)
    sn = _normalize(vn[tri].sum(axis=1))
    # where smoothing cancels out (degenerate/folded spots) fall back to the flat normal
    bad = np.linalg.norm(sn, axis=1) < 0.5
    sn[bad] = _normalize(fn[bad])
    return sn


def shade(base_rgb, normals, elev, azim, ambient=0.30, diffuse=0.72, specular=0.28, shininess=28.0):
    """Blinn-Phong, two-sided, directional key light above-left of the camera plus a weak fill.

    base_rgb: (M,3) albedo per face. Returns (M,4) RGBA in [0,1].
    """
    to_eye, right, up = camera_frame(elev, azim)
    key = _normalize(0.75 * to_eye + 0.55 * up - 0.35 * right)
    fill = _normalize(0.6 * to_eye - 0.3 * up + 0.6 * right)
    n = normals.copy()
    # two-sided lighting: turn every face towards the viewer
    n *= np.where(n @ to_eye < 0, -1.0, 1.0)[:, None]
    lam_key = np.clip(n @ key, 0.0, 1.0)
    lam_fill = np.clip(n @ fill, 0.0, 1.0)
    half = _normalize(key + to_eye)
    spec = np.clip(n @ half, 0.0, 1.0) ** shininess
    light = ambient + diffuse * lam_key + 0.18 * lam_fill
    rgb = base_rgb * light[:, None] + specular * spec[:, None]
    rgb = np.clip(rgb, 0.0, 1.0)
    return np.column_stack([rgb, np.ones(len(rgb))])


# -------------------------------------------------------------------------------------- drawing
def parse_size(s):
    try:
        w, h = (float(v) for v in s.lower().split("x"))
        if w <= 0 or h <= 0:
            raise ValueError
    except ValueError:
        raise argparse.ArgumentTypeError(f"bad --size '{s}' (want WxH in inches, e.g. 8x6)")
    return w, h


def scene_title(input_path):
    """(scene name, whether the series is stamped by time) from the run's summary.json next to vtk/, if any."""
    folder = os.path.dirname(os.path.abspath(input_path))
    for cand in (os.path.join(folder, "summary.json"), os.path.join(os.path.dirname(folder), "summary.json")):
        if os.path.isfile(cand):
            try:
                with open(cand) as f:
                    s = json.load(f)
            except (OSError, ValueError):
                continue
            solver = s.get("solver") or {}
            by_time = "haptics" in s or (isinstance(solver, dict) and "duration_s" in solver)
            return s.get("scene"), by_time
    return None, None


def tools_input(args, vtu, frame_index, stamp):
    """The tools surface (.vtu) that belongs to this wall frame, or None: vtk/tools.pvd (same index, else the
    nearest stamp) next to a surface .pvd, or tools_NNNN.vtu next to surface_NNNN.vtu."""
    if args.no_tools:
        return None
    if args.tools:
        src = args.tools
    elif args.input.lower().endswith(".pvd"):
        src = os.path.join(os.path.dirname(os.path.abspath(args.input)), "tools.pvd")
        if os.path.abspath(src) == os.path.abspath(args.input):
            return None
    else:
        base = os.path.basename(vtu)
        if not base.startswith("surface_"):
            return None
        src = os.path.join(os.path.dirname(os.path.abspath(vtu)), "tools_" + base[len("surface_"):])
    if not os.path.isfile(src):
        if args.tools:
            raise RenderError(f"{src}: not found (--tools)")
        return None
    if not src.lower().endswith(".pvd"):
        return src
    entries = read_pvd(src)
    wall = read_pvd(args.input) if args.input.lower().endswith(".pvd") else None
    if wall is not None and len(wall) == len(entries) and frame_index is not None:
        f = entries[frame_index][1]
    else:
        f = min(entries, key=lambda e: abs(e[0] - stamp) if stamp is not None and np.isfinite(stamp) else 0)[1]
    return f if os.path.isfile(f) else None


def load_frame(args, frame):
    """Everything one picture shows: the wall, optional nodes and tools, and the frame's description."""
    vtu, frame_desc = resolve_input(args.input, frame)
    index, stamp = None, None
    if args.input.lower().endswith(".pvd"):
        entries = read_pvd(args.input)
        index = (len(entries) - 1 if frame is None else frame) % len(entries)
        stamp = entries[index][0]
    surf = load_surface(vtu, args.outer_only)
    if args.color == "displacement" and surf["disp"] is None:
        raise RenderError(f"{vtu}: no point data 'displacement' (3 components) for --color displacement")
    nodes_mm = load_nodes(args.nodes, frame) * 1e3 if args.nodes else None
    tools = None
    tvtu = tools_input(args, vtu, index, stamp)
    if tvtu is not None:
        tools = load_surface(tvtu, False)
    return {"vtu": vtu, "desc": frame_desc, "stamp": stamp, "surf": surf, "nodes_mm": nodes_mm, "tools": tools}


def frame_limits(frames):
    """Axis limits (mm) holding every frame's wall and nodes, and the tools near them."""
    pts = []
    for fr in frames:
        pts.append(fr["surf"]["pts"][np.unique(fr["surf"]["tri"])] * 1e3)
        if fr["nodes_mm"] is not None and len(fr["nodes_mm"]):
            pts.append(fr["nodes_mm"])
    wall = np.vstack(pts)
    lo, hi = wall.min(axis=0), wall.max(axis=0)
    reach = 0.5 * max((hi - lo).max(), 1e-9)  # tools are drawn where they come within this of the wall's box
    for fr in frames:
        if fr["tools"] is not None:
            tp = fr["tools"]["pts"] * 1e3
            near = np.all((tp >= lo - reach) & (tp <= hi + reach), axis=1)
            if near.any():
                pts.append(tp[near])
    allpts = np.vstack(pts)
    lo, hi = allpts.min(axis=0), allpts.max(axis=0)
    span = hi - lo
    pad = 0.02 * max(span.max(), 1e-9)
    span = np.maximum(span, 0.02 * max(span.max(), 1e-9))  # flat data still gets a visible box
    mid = 0.5 * (lo + hi)
    return mid - 0.5 * span - pad, mid + 0.5 * span + pad


def frame_vmax(args, frames):
    if args.vmax is not None:
        return args.vmax
    vmax = 0.0
    for fr in frames:
        s = fr["surf"]
        if s["disp"] is not None:
            vmax = max(vmax, float(np.nanmax(np.linalg.norm(s["disp"], axis=1)[np.unique(s["tri"])]) * 1e3))
    return vmax if vmax > 0 else 1e-3  # undeformed frame: keep a valid, readable scale


def draw(fig, fr, args, limits, vmax, title):
    """Draws one frame into `fig` (cleared first)."""
    import matplotlib
    import matplotlib.pyplot as plt
    from matplotlib import cm, colors
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    fig.clf()
    surf, nodes_mm = fr["surf"], fr["nodes_mm"]
    pts_mm = surf["pts"] * 1e3
    tri = surf["tri"]
    M = len(tri)
    lo, hi = limits

    if args.color == "displacement":
        umag = np.linalg.norm(surf["disp"], axis=1) * 1e3  # mm
        face_u = umag[tri].mean(axis=1)
        norm = colors.Normalize(vmin=0.0, vmax=vmax)
        cmap = plt.get_cmap(args.cmap)
        base = cmap(norm(face_u))[:, :3]
    else:
        base = np.tile(colors.to_rgb(args.tissue_color), (M, 1))
    if surf["outer"] is not None:
        base = base * np.where(surf["outer"] == 1, 1.0, INNER_DIM)[:, None]

    normals = face_shading_normals(pts_mm, tri, surf["normal"])
    fc = shade(base, normals, args.elev, args.azim)
    alpha = args.alpha if args.alpha is not None else (0.35 if nodes_mm is not None else 1.0)
    fc[:, 3] = alpha

    w, h = args.size
    # the 3-D box is drawn inside the axes with generous room for tick labels; let it fill the figure
    # (title: fixed room in inches at the top, so it never clips on small figures)
    fig.subplots_adjust(left=0.0, right=1.0 - 1.25 / w if args.color == "displacement" else 1.0, bottom=0.0,
                        top=max(0.5, 1.0 - 0.5 / h))
    ax = fig.add_subplot(projection="3d")
    ax.view_init(elev=args.elev, azim=args.azim)
    ax.set_proj_type("persp", focal_length=args.focal_length)

    verts = pts_mm[tri]  # (M,3,3)
    # edges in the face colour hide the hairline cracks Agg leaves between antialiased triangles
    ec = fc.copy()
    if alpha < 1.0:
        ec[:, 3] = 0.0
    coll = Poly3DCollection(verts, facecolors=fc, edgecolors=ec, linewidths=0.3 if alpha >= 1.0 else 0.0)
    ax.add_collection3d(coll)

    tools = fr["tools"]
    if tools is not None:
        tp = tools["pts"] * 1e3
        inside = np.all((tp >= lo - 1e-9) & (tp <= hi + 1e-9), axis=1)
        keep = inside[tools["tri"]].all(axis=1)  # matplotlib does not clip 3-D polygons to the box
        if keep.any():
            ttri = tools["tri"][keep]
            tn = face_shading_normals(tp, ttri, tools["normal"])
            tfc = shade(np.tile(colors.to_rgb(TOOL_RGB), (len(ttri), 1)), tn, args.elev, args.azim)
            ax.add_collection3d(Poly3DCollection(tp[ttri], facecolors=tfc, edgecolors=tfc, linewidths=0.2))

    if nodes_mm is not None and len(nodes_mm):
        ax.computed_zorder = False  # dots on top of the translucent wall
        coll.set_zorder(1)
        ax.scatter(nodes_mm[:, 0], nodes_mm[:, 1], nodes_mm[:, 2], s=args.node_size, c=[NODE_RGB],
                   depthshade=False, linewidths=0, zorder=2, label=f"nodes ({len(nodes_mm)})")
        ax.legend(loc="upper right", fontsize=8, frameon=False)

    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    ax.set_box_aspect(tuple(hi - lo), zoom=args.zoom)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_zlabel("z (mm)")
    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        axis.set_pane_color((0.95, 0.95, 0.96, 1.0))
        axis._axinfo["grid"]["color"] = (0.82, 0.82, 0.85, 1.0)
        axis._axinfo["grid"]["linewidth"] = 0.5
        axis.set_major_locator(matplotlib.ticker.MaxNLocator(5))
    ax.tick_params(labelsize=8)

    sub = [fr["desc"]] if fr["desc"] else []
    sub.append(f"{M} triangles" + (" (outer wall)" if args.outer_only and surf["outer"] is not None else ""))
    if tools is not None:
        sub.append("tool in grey")
    fig.suptitle(title if args.no_subtitle else f"{title}\n" + ", ".join(sub), fontsize=10, y=1.0 - 0.06 / h, va="top")

    if args.color == "displacement":
        sm = cm.ScalarMappable(norm=norm, cmap=cmap)
        sm.set_array([])
        cax = fig.add_axes([1.0 - 1.0 / w, 0.28, 0.13 / w, 0.44])  # right margin: 1 in for bar + labels
        cb = fig.colorbar(sm, cax=cax)
        cb.set_label("|u| (mm)")


def describe_stamp(fr, by_time):
    """The frame's line under the title: its time or load factor when the run says which."""
    if fr["stamp"] is None or by_time is None or not fr["desc"]:
        return fr["desc"]
    head = fr["desc"].split(", timestep")[0]
    return f"{head}, t = {fr['stamp']:.4g} s" if by_time else f"{head}, load factor {fr['stamp']:.3g}"


def render(args):
    t0 = time.perf_counter()
    out_dir = os.path.dirname(os.path.abspath(args.out))
    if not os.path.isdir(out_dir):
        raise RenderError(f"{args.out}: output folder does not exist")
    fr = load_frame(args, args.frame)
    scene, by_time = scene_title(args.input)
    fr["desc"] = describe_stamp(fr, by_time)
    title = args.title if args.title is not None else (scene or os.path.splitext(os.path.basename(args.input))[0])

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=args.size, dpi=args.dpi)
    draw(fig, fr, args, frame_limits([fr]), frame_vmax(args, [fr]), title)
    try:
        fig.savefig(args.out, dpi=args.dpi)
    except OSError as e:
        raise RenderError(f"{args.out}: cannot write: {e.strerror or e}")
    plt.close(fig)
    if args.verbose:
        print(f"{PROG}: {len(fr['surf']['tri'])} triangles in {time.perf_counter() - t0:.1f} s", file=sys.stderr)
    return args.out


def render_all(args):
    """Every frame of a .pvd: OUT/frame_NNNN.png, and OUT/animation.gif unless --no-gif; one colour scale and
    one set of axes for all frames, so the picture moves only where the wall does."""
    if not args.input.lower().endswith(".pvd"):
        raise RenderError(f"{args.input}: --all-frames needs a .pvd series")
    out_dir = os.path.abspath(args.out)
    if os.path.isfile(out_dir):
        raise RenderError(f"{args.out}: --all-frames writes into a folder, and this is a file")
    os.makedirs(out_dir, exist_ok=True)
    n = len(read_pvd(args.input))
    frames = [load_frame(args, i) for i in range(n)]
    scene, by_time = scene_title(args.input)
    for fr in frames:
        fr["desc"] = describe_stamp(fr, by_time)
    title = args.title if args.title is not None else (scene or os.path.splitext(os.path.basename(args.input))[0])
    limits, vmax = frame_limits(frames), frame_vmax(args, frames)

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.animation import PillowWriter

    fig = plt.figure(figsize=args.size, dpi=args.dpi)
    gif = None if args.no_gif else os.path.join(out_dir, "animation.gif")
    writer = PillowWriter(fps=args.fps) if gif else None
    written = []
    try:
        if writer:
            writer.setup(fig, gif, dpi=args.dpi)
        for i, fr in enumerate(frames):
            draw(fig, fr, args, limits, vmax, title)
            png = os.path.join(out_dir, f"frame_{i:04d}.png")
            fig.savefig(png, dpi=args.dpi)
            written.append(png)
            if writer:
                writer.grab_frame()
        if writer:
            writer.finish()
            written.append(gif)
    except OSError as e:
        raise RenderError(f"{args.out}: cannot write: {e.strerror or e}")
    plt.close(fig)
    return written


def main(argv=None):
    ap = argparse.ArgumentParser(prog="render_surface.py", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("input", help="surface .vtu, or a .pvd collection of them")
    ap.add_argument("--out", required=True, help="PNG file to write (with --all-frames: the folder for the frames)")
    ap.add_argument("--all-frames", action="store_true", help="every frame of the .pvd: OUT/frame_NNNN.png and an "
                    "animated OUT/animation.gif (one colour scale and one view for all)")
    ap.add_argument("--no-gif", action="store_true", help="with --all-frames: only the PNG frames")
    ap.add_argument("--fps", type=float, default=5.0, help="frames per second of the GIF (default 5)")
    ap.add_argument("--tools", help="the tools' surface (.vtu or .pvd; default: vtk/tools.pvd or tools_NNNN.vtu "
                    "next to the input, when the run wrote one)")
    ap.add_argument("--no-tools", action="store_true", help="do not draw the tools")
    ap.add_argument("--frame", type=int, help="frame index in a .pvd (0-based, negative counts from the end; "
                    "default: last)")
    ap.add_argument("--color", choices=["tissue", "displacement"], default="tissue",
                    help="uniform tissue colour (default) or |displacement| in mm with a colourbar")
    ap.add_argument("--title", help="figure title (default: the scene's name from the run's summary.json, else "
                    "the input file stem)")
    ap.add_argument("--no-subtitle", action="store_true", help="omit the frame / triangle-count line")
    ap.add_argument("--elev", type=float, default=22.0, help="camera elevation in degrees (default 22)")
    ap.add_argument("--azim", type=float, default=-58.0, help="camera azimuth in degrees (default -58)")
    ap.add_argument("--outer-only", action="store_true", help="draw only triangles with cell data outer == 1")
    ap.add_argument("--nodes", help="also draw node positions from this .vtu (or .pvd, same --frame) as dots; "
                    "the wall is then drawn translucent")
    ap.add_argument("--dpi", type=float, default=150, help="resolution (default 150)")
    ap.add_argument("--size", type=parse_size, default=(8.0, 6.0), help="figure size WxH in inches (default 8x6)")
    ap.add_argument("--tissue-color", default="#cc545c", help="wall colour for --color tissue (default #cc545c)")
    ap.add_argument("--cmap", default="Spectral_r", help="colormap for --color displacement (default Spectral_r)")
    ap.add_argument("--vmax", type=float, help="upper end of the |u| colour scale in mm (default: data max; "
                    "fix it to compare frames)")
    ap.add_argument("--alpha", type=float, help="wall opacity (default 1, or 0.35 with --nodes)")
    ap.add_argument("--node-size", type=float, default=2.0, help="marker size of --nodes dots (default 2)")
    ap.add_argument("--zoom", type=float, default=1.05, help="zoom of the 3-D box (default 1.05)")
    ap.add_argument("--focal-length", type=float, default=2.0,
                    help="perspective focal length; larger is flatter (default 2)")
    ap.add_argument("-v", "--verbose", action="store_true", help="print timing on stderr")
    args = ap.parse_args(argv)
    if args.dpi <= 0:
        ap.error("--dpi must be positive")
    if args.alpha is not None and not 0.0 <= args.alpha <= 1.0:
        ap.error("--alpha must be in [0, 1]")
    import matplotlib.colors

    if not matplotlib.colors.is_color_like(args.tissue_color):
        ap.error(f"--tissue-color: not a colour: {args.tissue_color}")
    if args.cmap not in matplotlib.colormaps:
        ap.error(f"--cmap: unknown colormap '{args.cmap}'")
    if args.vmax is not None and not args.vmax > 0:
        ap.error("--vmax must be positive")
    if args.fps <= 0:
        ap.error("--fps must be positive")
    try:
        out = render_all(args) if args.all_frames else [render(args)]
    except RenderError as e:
        print(f"{PROG}: {e}", file=sys.stderr)
        return 2
    print("\n".join(out))
    return 0


if __name__ == "__main__":
    sys.exit(main())

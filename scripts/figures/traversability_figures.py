#!/usr/bin/python3
"""Figures of a traversability map folder (`terramesh` map exports, docs/formats.md).

Inputs (MAP is the folder):
  MAP/traversability.ply  binary PLY: vertex x y z (mesh frame, map units); per-face cost (float,
                          [0,1], NaN = unknown), lethal, unknown and uncertain (uchar flags; uncertain optional), and the layers
                          slope_deg, contact, step_m, roughness_m (float; optional for the figures)
  MAP/map_frame.yaml      up: [x, y, z] and metres_per_unit (plan_x, plan_y when present): a mesh
                          point p is drawn at (plan_x . p, plan_y . p) * metres_per_unit
  --path [LABEL=]FILE     planned path(s), CSV with header x,y,z[,yaw,face,cost] (repeatable;
                          default MAP/path.csv if it exists); x,y,z in the mesh frame like the
                          PLY, or in plan metres with --path-frame plan
  --trajectory FILE       camera trajectory, KITTI poses (12 numbers per line, camera-to-world,
                          mesh frame), e.g. the generator's trajectory.txt
Outputs (default MAP/plots):
  traversability_top.png         top view, faces coloured by cost, unknown grey, lethal red, uncertain magenta, with
                                 the trajectory and the paths; upper faces drawn over lower ones
  traversability_top_detail.png  the same top view over a --detail-m (40 m) wide window around the
                                 middle of the first path (or of the trajectory), where the strip a
                                 robot drove is wide enough to see; only when the map is wider
  traversability_reasons.png     the same top view coloured by why a face is not free (its
                                 `reasons` bits, named by the PLY's "reasons bits" header comment;
                                 when the map has both)
  traversability_histograms.png  area of known faces per slope, contact, step and roughness bin,
                                 traversable and lethal stacked
Exit codes: 0 done, 2 missing or malformed input (message on stderr).

  scripts/figures/traversability_figures.py out/map --trajectory out/street/trajectory.txt
"""

import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
import numpy as np  # noqa: E402
import ply  # noqa: E402

UNKNOWN_RGBA = (0.62, 0.62, 0.62, 1.0)
LETHAL_RGBA = (0.85, 0.0, 0.0, 1.0)
# Uncertain faces (measured, the evidence cannot decide): magenta, as in the viewer.
UNCERTAIN_RGBA = (235 / 255, 60 / 255, 190 / 255, 1.0)
PATH_COLOURS = ["cyan", "darkorange", "black", "lime", "saddlebrown", "blue"]  # not magenta: uncertain faces
TOP_VIEW_SIZE_IN = (12.0, 10.0)
# Why a face is not free (traversability.ply's `reasons` bits, docs/traversability.md): a face takes
# the first group, in this order, that has one of its bits. Reds: lethal; purples and pinks:
# uncertain; grey: unknown.
REASON_GROUPS = [
    ("lethal: too steep", (0.55, 0.0, 0.0, 1.0), ["too_steep"]),
    ("lethal: no heading fits", (0.9, 0.1, 0.1, 1.0), ["no_heading_fits"]),
    ("lethal: low clearance", (1.0, 0.55, 0.3, 1.0), ["low_clearance"]),
    ("uncertain: possible step", (0.45, 0.1, 0.6, 1.0), ["possible_step"]),
    ("uncertain: guessed wall or ceiling", (0.3, 0.3, 0.75, 1.0), ["guessed_wall", "unknown_low_clearance",
                                                                   "seen_from_behind"]),
    ("uncertain: slope within noise", (0.95, 0.55, 0.8, 1.0), ["slope_may_exceed"]),
    ("uncertain: relief", (0.85, 0.2, 0.65, 1.0), ["worst_case_relief"]),
    ("uncertain: possible obstacle", (0.6, 0.45, 0.95, 1.0), ["possible_obstacle", "obstacle_extension",
                                                              "unconfirmed_point"]),
    ("unknown", UNKNOWN_RGBA, ["closing_geometry", "few_rays"]),
]
# traversability.ply names the bits in a header comment (terramesh writes it from its registry).
REASON_BITS_COMMENT = "reasons bits, lowest first:"
FREE_RGBA = (0.55, 0.8, 0.55, 1.0)
OTHER_REASON_RGBA = (0.3, 0.3, 0.3, 1.0)

HISTOGRAMS = [("slope_deg", "slope (degrees)", np.arange(0.0, 90.0 + 1e-9, 2.0)),
              ("contact", "ground contact (fraction of the footprint)", np.linspace(0.0, 1.0, 41)),
              ("step_m", "step height (m)", None),
              ("roughness_m", "roughness (m)", None)]


def parse_args(argv):
    parser = argparse.ArgumentParser(
        description="Draws a top view and layer histograms of a traversability map folder.",
        epilog="Exit codes: 0 done, 2 missing or malformed input.")
    parser.add_argument("map_dir", metavar="MAP", help="folder with traversability.ply and map_frame.yaml")
    parser.add_argument("--ply", metavar="FILE", help="the layered mesh (default: MAP/traversability.ply)")
    parser.add_argument("--frame", metavar="FILE", help="the map frame (default: MAP/map_frame.yaml)")
    parser.add_argument("--path", metavar="[LABEL=]FILE", action="append", default=[],
                        help="a planned path CSV (x,y,z,...); repeat for several (default: MAP/path.csv if present)")
    parser.add_argument("--path-frame", choices=["mesh", "plan"], default="mesh",
                        help="x,y,z of the paths: mesh frame like the PLY (default), or plan metres")
    parser.add_argument("--trajectory", metavar="FILE", help="camera trajectory, KITTI pose format")
    parser.add_argument("--detail-m", type=float, default=40.0, metavar="W",
                        help="width of the detail view in metres (0: none; default 40)")
    parser.add_argument("-o", "--output-dir", metavar="OUT", help="where the PNGs go (default: MAP/plots)")
    parser.add_argument("--show-steiner", action="store_true",
                        help="also draw the faces through Steiner vertices (the lid that closes the map)")
    return parser.parse_args(argv)


def read_frame(path):
    """(up, plan_x, plan_y, metres_per_unit) of a map_frame.yaml; axes are unit numpy vectors."""
    common.require_file(path)
    try:
        import yaml
    except ImportError:
        sys.exit("traversability_figures.py: needs PyYAML (Debian: python3-yaml)")
    try:
        with open(path, encoding="utf-8") as handle:
            root = yaml.safe_load(handle)
    except yaml.YAMLError as error:
        mark = getattr(error, "problem_mark", None)
        where = f"line {mark.line + 1}" if mark else ""
        raise common.InputError(path, where, f"malformed YAML ({getattr(error, 'problem', error)})") from None
    if not isinstance(root, dict):
        raise common.InputError(path, "", "expected a YAML mapping with keys up and metres_per_unit")

    def vector(key, required):
        value = root.get(key)
        if value is None and not required:
            return None
        if not isinstance(value, list) or len(value) != 3:
            raise common.InputError(path, f"key {key}", "expected [x, y, z]")
        try:
            array = np.array([float(v) for v in value])
        except (TypeError, ValueError):
            raise common.InputError(path, f"key {key}", "expected three numbers") from None
        if not np.all(np.isfinite(array)) or np.linalg.norm(array) < 1e-12:
            raise common.InputError(path, f"key {key}", "expected a finite non-zero vector")
        return array / np.linalg.norm(array)

    up = vector("up", True)
    scale = root.get("metres_per_unit")
    if isinstance(scale, bool) or not isinstance(scale, (int, float)) or not np.isfinite(scale) or scale <= 0:
        raise common.InputError(path, "key metres_per_unit", "expected a positive number")
    plan_x = vector("plan_x", False)
    plan_y = vector("plan_y", False)
    if plan_x is None or plan_y is None:
        # As MapPlane::fromUp: the mesh x axis projected on the plane, y if x is within 30 degrees of up.
        reference = np.array([1.0, 0.0, 0.0])
        if abs(reference @ up) > np.cos(np.radians(30.0)):
            reference = np.array([0.0, 1.0, 0.0])
        plan_x = reference - (reference @ up) * up
        plan_x /= np.linalg.norm(plan_x)
        plan_y = np.cross(up, plan_x)
    return up, plan_x, plan_y, float(scale)


def read_map(path):
    """(vertices (N,3), faces list or (F,3) array, {layer: (F,) float array}) of traversability.ply."""
    elements = ply.read(path)
    for name in ("vertex", "face"):
        if name not in elements:
            raise common.InputError(path, "header", f"missing element \"{name}\"")
    vertex, face = elements["vertex"], elements["face"]
    for name in ("x", "y", "z"):
        if name not in vertex:
            raise common.InputError(path, "element vertex", f"missing property \"{name}\"")
    for name in ("vertex_indices", "cost", "lethal", "unknown"):
        if name not in face:
            raise common.InputError(path, "element face", f"missing property \"{name}\"")
    if face.count == 0:
        raise common.InputError(path, "element face", "holds no face")
    vertices = np.column_stack([vertex["x"], vertex["y"], vertex["z"]]).astype(float)
    faces = face["vertex_indices"]
    polygons = [faces] if isinstance(faces, np.ndarray) else faces
    for polygon in polygons:
        if np.size(polygon) and (np.min(polygon) < 0 or np.max(polygon) >= len(vertices)):
            raise common.InputError(path, "element face", "vertex index out of range")
    layers = {prop.name: face[prop.name].astype(float) for prop in face.properties if not prop.is_list}
    return vertices, faces, layers


def read_path(spec):
    """(label, (N, 3) points) of a path CSV given as FILE or LABEL=FILE."""
    label, file = "", spec
    if "=" in spec and not os.path.exists(spec):
        label, _, file = spec.partition("=")
    label = label or os.path.splitext(os.path.basename(file))[0]
    rows = common.read_csv(file, ["x", "y", "z"])
    if not rows:
        raise common.InputError(file, "", "holds no waypoint")
    points = np.array([[common.number(file, row, key) for key in ("x", "y", "z")] for row in rows])
    return label, points


def faces_area_m2(xyz_m, faces):
    """Surface area of each face, m^2 (triangle fan for polygons)."""
    if isinstance(faces, np.ndarray) and faces.shape[1] == 3:
        p = xyz_m[faces]
        return 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
    polygons = list(faces)
    areas = np.zeros(len(polygons))
    for i, polygon in enumerate(polygons):
        p = xyz_m[polygon]
        for k in range(1, len(polygon) - 1):
            areas[i] += 0.5 * np.linalg.norm(np.cross(p[k] - p[0], p[k + 1] - p[0]))
    return areas


def top_view_faces(vertices, faces, layers, up, show_steiner):
    """Mask of the faces drawn in the top view: upward-facing, and measured unless show_steiner."""
    keep = np.ones(len(layers["cost"]), dtype=bool)
    if not show_steiner and "steiner" in layers:
        keep &= layers["steiner"] == 0
    if isinstance(faces, np.ndarray):
        p = vertices[faces]
        normals = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
        keep &= normals @ up > 0
    return keep


def draw_order(vertices, faces, up, scale):
    """Indices of the faces from the lowest to the highest (upper faces drawn over lower ones)."""
    height = (vertices @ up) * scale
    if isinstance(faces, np.ndarray):
        return np.argsort(height[faces].mean(axis=1), kind="stable")
    return np.argsort([height[polygon].mean() for polygon in faces], kind="stable")


def class_colours(plt, layers):
    """Per face: the cost on viridis, unknown grey, lethal red, uncertain magenta."""
    colours = plt.get_cmap("viridis")(np.clip(np.nan_to_num(layers["cost"], nan=0.0), 0.0, 1.0))
    colours[layers["unknown"] != 0] = UNKNOWN_RGBA
    colours[layers["lethal"] != 0] = LETHAL_RGBA
    if "uncertain" in layers:
        colours[layers["uncertain"] != 0] = UNCERTAIN_RGBA
    return colours


def reason_bit_names(path):
    """The names of the `reasons` bits, lowest first, from the PLY's header comment (None without it)."""
    for text in ply.comments(path):
        if text.startswith(REASON_BITS_COMMENT):
            return text[len(REASON_BITS_COMMENT):].split()
    return None


def reason_colours(layers, bit_names):
    """Per face: its first REASON_GROUPS group with one of its `reasons` bits, else FREE_RGBA; and
    the legend patches of the groups that occur."""
    from matplotlib.patches import Patch
    bits = layers["reasons"].astype(np.int64)
    colours = np.tile(np.array(FREE_RGBA), (len(bits), 1))
    done = np.zeros(len(bits), dtype=bool)
    handles = [Patch(color=FREE_RGBA, label="free")]
    for label, rgba, names in REASON_GROUPS:
        mask = np.zeros(len(bits), dtype=np.int64)
        for name in names:
            if name in bit_names:
                mask |= 1 << bit_names.index(name)
        hit = ((bits & mask) != 0) & ~done
        if hit.any():
            colours[hit] = rgba
            handles.append(Patch(color=rgba, label=label))
        done |= hit
    # A bit no group names (a reason newer than this script) is still not free.
    other = (bits != 0) & ~done
    if other.any():
        colours[other] = OTHER_REASON_RGBA
        handles.append(Patch(color=OTHER_REASON_RGBA, label="another reason"))
    return colours, handles


def top_view(plt, vertices, faces, colours, frame, paths, trajectory, title, handles, colorbar=True, window=None):
    """Top view of the faces in `colours` (per face RGBA, the faces' order), with the trajectory
    and the paths; over `window` ((x0, x1), (y0, y1) in plan metres) if given, else over all."""
    from matplotlib.collections import PolyCollection
    from matplotlib.lines import Line2D
    up, plan_x, plan_y, scale = frame
    plan = np.column_stack([vertices @ plan_x, vertices @ plan_y]) * scale
    order = draw_order(vertices, faces, up, scale)
    polygons = plan[faces[order]] if isinstance(faces, np.ndarray) else [plan[faces[i]] for i in order]

    figure, axes = plt.subplots(figsize=TOP_VIEW_SIZE_IN, dpi=common.FIGURE_DPI)
    # No antialiasing: it would show the background through the seams between faces.
    axes.add_collection(PolyCollection(polygons, facecolors=colours[order], edgecolors="none", antialiaseds=False))
    handles = list(handles)
    points = [plan]
    if trajectory is not None:
        xy = np.column_stack([trajectory @ plan_x, trajectory @ plan_y]) * scale
        # Thin in a detail view: the strip the robot drove lies under it.
        axes.plot(xy[:, 0], xy[:, 1], color="black", linestyle="--", linewidth=0.6 if window else 1.2)
        axes.plot(xy[0, 0], xy[0, 1], marker="o", color="black")
        handles.append(Line2D([], [], color="black", linestyle="--", label="camera trajectory"))
        points.append(xy)
    for i, (label, xy) in enumerate(paths):
        colour = PATH_COLOURS[i % len(PATH_COLOURS)]
        axes.plot(xy[:, 0], xy[:, 1], color=colour, linewidth=2.0)
        axes.plot(xy[0, 0], xy[0, 1], marker="o", color=colour)
        axes.plot(xy[-1, 0], xy[-1, 1], marker="*", markersize=12, color=colour)
        handles.append(Line2D([], [], color=colour, linewidth=2.0, label=f"path: {label}"))
        points.append(xy)
    everything = np.vstack(points)
    low, high = everything.min(axis=0), everything.max(axis=0)
    margin = 0.03 * max(float(np.max(high - low)), 1e-6)
    axes.set_xlim(window[0] if window else (low[0] - margin, high[0] + margin))
    axes.set_ylim(window[1] if window else (low[1] - margin, high[1] + margin))
    axes.set_aspect("equal")
    axes.set_xlabel("plan x (m)")
    axes.set_ylabel("plan y (m)")
    axes.set_title(title)
    if colorbar:
        mappable = plt.cm.ScalarMappable(cmap=plt.get_cmap("viridis"), norm=plt.Normalize(0.0, 1.0))
        figure.colorbar(mappable, ax=axes, label="cost", fraction=0.04, pad=0.02)
    axes.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, -0.07), ncol=min(len(handles), 4))
    figure.set_layout_engine("tight")
    return figure


def histograms(plt, layers, areas):
    figure, grid = plt.subplots(2, 2, figsize=common.FIGURE_SIZE_IN, dpi=common.FIGURE_DPI)
    known = layers["unknown"] == 0
    if "uncertain" in layers:
        known = known & (layers["uncertain"] == 0)
    lethal = layers["lethal"] != 0
    for axes, (name, label, bins) in zip(grid.ravel(), HISTOGRAMS):
        axes.set_xlabel(label)
        axes.set_ylabel("area (m²)")
        if name not in layers:
            axes.text(0.5, 0.5, f"no {name} in the map", ha="center", va="center", transform=axes.transAxes)
            continue
        values = layers[name]
        use = known & np.isfinite(values)
        if not np.any(use):
            axes.text(0.5, 0.5, f"no finite {name} on known faces", ha="center", va="center",
                      transform=axes.transAxes)
            continue
        if bins is None:
            bins = np.linspace(0.0, max(float(np.percentile(values[use], 99.5)), 1e-3), 41)
        axes.hist([np.clip(values[use & ~lethal], bins[0], bins[-1]), np.clip(values[use & lethal], bins[0], bins[-1])],
                  bins=bins, weights=[areas[use & ~lethal], areas[use & lethal]], stacked=True,
                  color=[plt.get_cmap("viridis")(0.35), LETHAL_RGBA], label=["traversable", "lethal"])
        axes.legend(loc="upper right")
    figure.suptitle("Free and lethal faces by layer (unknown and uncertain left out; values past the last bin "
                    "counted in it)")
    figure.set_layout_engine("tight")
    return figure


def detail_window(paths, trajectory_xy, extent, width_m):
    """The detail view's ((x0, x1), (y0, y1)): `width_m` wide, 0.8 of that high, centred on the
    middle (by length) of the first path, else of the trajectory; None without either, or when the
    whole view (`extent`, its larger side) is no wider."""
    line = paths[0][1] if paths else trajectory_xy
    if width_m <= 0 or line is None or len(line) == 0 or width_m >= extent:
        return None
    along = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(line, axis=0), axis=1))])
    centre = np.array([np.interp(0.5 * along[-1], along, line[:, k]) for k in range(2)])
    return ((centre[0] - 0.5 * width_m, centre[0] + 0.5 * width_m),
            (centre[1] - 0.4 * width_m, centre[1] + 0.4 * width_m))


def class_shares(areas, layers):
    """The text "P% traversable, P% lethal, P% uncertain, P% unknown" of these faces, by area."""
    total = max(float(areas.sum()), 1e-12)
    unknown = layers["unknown"] != 0
    lethal = (layers["lethal"] != 0) & ~unknown
    uncertain = (layers["uncertain"] != 0) if "uncertain" in layers else np.zeros(len(areas), bool)
    return (f"{100 * areas[~unknown & ~lethal & ~uncertain].sum() / total:.1f}% traversable, "
            f"{100 * areas[lethal].sum() / total:.1f}% lethal, "
            f"{100 * areas[uncertain].sum() / total:.1f}% uncertain, "
            f"{100 * areas[unknown].sum() / total:.1f}% unknown")


def detail_view(plt, args, vertices, faces, layers, areas, frame, paths, trajectory, handles, output_dir):
    """traversability_top_detail.png (a list of the one file written, or empty)."""
    up, plan_x, plan_y, scale = frame
    plan = np.column_stack([vertices @ plan_x, vertices @ plan_y]) * scale
    trajectory_xy = None if trajectory is None else np.column_stack([trajectory @ plan_x, trajectory @ plan_y]) * scale
    lines = [plan] + [xy for _, xy in paths] + ([trajectory_xy] if trajectory_xy is not None else [])
    everything = np.vstack(lines)
    window = detail_window(paths, trajectory_xy, float(np.max(everything.max(axis=0) - everything.min(axis=0))),
                           args.detail_m)
    if window is None:
        return []
    centroids = np.array([plan[f].mean(axis=0) for f in faces]) if len(faces) else np.zeros((0, 2))
    inside = ((centroids[:, 0] >= window[0][0]) & (centroids[:, 0] <= window[0][1]) &
              (centroids[:, 1] >= window[1][0]) & (centroids[:, 1] <= window[1][1]))
    what = "the path's" if paths else "the trajectory's"
    title = (f"Traversability, {args.detail_m:g} m around {what} middle; the faces centred here, by their area:\n"
             + class_shares(areas[inside], {name: values[inside] for name, values in layers.items()}))
    figure = top_view(plt, vertices, faces, class_colours(plt, layers), frame, paths, trajectory, title, handles,
                      window=window)
    path = common.save_png(figure, os.path.join(output_dir, "traversability_top_detail.png"))
    plt.close(figure)
    return [path]


def main(argv=None):
    args = parse_args(argv)
    ply_path = args.ply or os.path.join(args.map_dir, "traversability.ply")
    frame = read_frame(args.frame or os.path.join(args.map_dir, "map_frame.yaml"))
    vertices, faces, layers = read_map(ply_path)
    specs = args.path
    default_path = os.path.join(args.map_dir, "path.csv")
    if not specs and os.path.isfile(default_path):
        specs = [default_path]
    up, plan_x, plan_y, scale = frame
    paths = []
    for spec in specs:
        label, points = read_path(spec)
        if args.path_frame == "mesh":
            points = np.column_stack([points @ plan_x, points @ plan_y]) * scale
        paths.append((label, points[:, :2]))
    trajectory = common.read_kitti_positions(args.trajectory) if args.trajectory else None

    areas = faces_area_m2(vertices * scale, faces)
    output_dir = args.output_dir or os.path.join(args.map_dir, "plots")
    plt = common.pyplot()
    from matplotlib.patches import Patch
    written = []
    # The top view shows the ground: faces that face up and were measured. The closed mesh's lid
    # (Steiner faces) and the undersides of things would otherwise hide it. Its shares are of
    # what it shows.
    shown = top_view_faces(vertices, faces, layers, up, args.show_steiner)
    view_faces = faces[shown] if isinstance(faces, np.ndarray) else [f for f, keep in zip(faces, shown) if keep]
    view_layers = {name: values[shown] for name, values in layers.items()}
    shown_areas = areas[shown]
    counts = (f"{len(view_layers['cost'])} of {len(areas)} faces drawn (facing up"
              f"{'' if args.show_steiner else ', measured'}); by their area:\n"
              + class_shares(shown_areas, view_layers))
    class_handles = [Patch(color=UNKNOWN_RGBA, label="unknown"), Patch(color=LETHAL_RGBA, label="lethal"),
                     Patch(color=UNCERTAIN_RGBA, label="uncertain")]
    figure = top_view(plt, vertices, view_faces, class_colours(plt, view_layers), frame, paths, trajectory,
                      "Traversability, top view\n" + counts, class_handles)
    written.append(common.save_png(figure, os.path.join(output_dir, "traversability_top.png")))
    plt.close(figure)
    written += detail_view(plt, args, vertices, view_faces, view_layers, shown_areas, frame, paths, trajectory,
                           class_handles, output_dir)
    bit_names = reason_bit_names(ply_path)
    if "reasons" in view_layers and bit_names:
        colours, handles = reason_colours(view_layers, bit_names)
        figure = top_view(plt, vertices, view_faces, colours, frame, paths, trajectory,
                          "Why not free, top view (the first reason of each face)\n" + counts, handles,
                          colorbar=False)
        written.append(common.save_png(figure, os.path.join(output_dir, "traversability_reasons.png")))
        plt.close(figure)
    figure = histograms(plt, layers, areas)
    written.append(common.save_png(figure, os.path.join(output_dir, "traversability_histograms.png")))
    plt.close(figure)
    for path in written:
        print(path)
    return common.EXIT_OK


if __name__ == "__main__":
    common.run_main(main)

"""Reads m2rc's robot-frame outputs back with independent readers and checks every pose against
the route's cells.

    python3 scripts/robot_roundtrip.py M2RC MAP PROGRAM OUTDIR

Runs `M2RC compile PROGRAM --map MAP` once per `--emit` (route, nav-path, waypoints, geojson,
mcap), then reads the YAML with PyYAML, the MCAP container with the `mcap` package and its CDR
messages with `rosbags` (its own ROS 2 Humble message definitions, not the schemas m2rc wrote),
and checks each position against the map-frame rule of docs/maps.md computed here from the
map file: centre of [row, col] = origin + R(yaw) ((col + 0.5) res, (row + 0.5) res).
Prints `robot round trip: N passed, 0 failed` and exits 0, or exits 1 on the first mismatch.
"""
import json
import math
import subprocess
import sys

import yaml
from mcap.reader import make_reader
from rosbags.typesys import Stores, get_typestore

m2rc, map_path, program, outdir = sys.argv[1:5]
passed = 0


def check(cond, what):
    global passed
    if not cond:
        print(f"FAILED: {what}")
        sys.exit(1)
    passed += 1


def compile_to(emit, out):
    subprocess.run([m2rc, "compile", program, "--map", map_path, "--emit", emit, "-o", out],
                   check=True, stdout=subprocess.DEVNULL)


def frame_of(map_path):
    if map_path == "demo":
        subprocess.run([m2rc, "map", "import", "demo", "-o", f"{outdir}/demo.json"], check=True,
                       stdout=subprocess.DEVNULL)
        map_path = f"{outdir}/demo.json"
    with open(map_path) as f:
        meta = json.load(f)["metadata"]
    res = meta["grid_coordinate_frame"]["resolution"]
    if "map_frame" in meta:
        ox, oy, yaw = meta["map_frame"]["origin"]
    else:
        g = meta["grid_coordinate_frame"]
        ox, oy, yaw = g["x_min"] - res / 2, g["z_min"] - res / 2, 0.0
    return res, ox, oy, yaw


res, ox, oy, yaw = frame_of(map_path)


def cell_xy(cell):
    r, c = cell
    u, v = (c + 0.5) * res, (r + 0.5) * res
    return (ox + math.cos(yaw) * u - math.sin(yaw) * v, oy + math.sin(yaw) * u + math.cos(yaw) * v)


def close(a, b, tol=1e-3):
    return abs(a[0] - b[0]) <= tol and abs(a[1] - b[1]) <= tol


compile_to("route", f"{outdir}/route.json")
with open(f"{outdir}/route.json") as f:
    route = json.load(f)
cells = route["trajectory"]
ends = [s["end_index"] for s in route["m2rc"]["stages"]]
expected = [cell_xy(c) for c in cells]
check(len(cells) > 1, "the route has more than one cell")


def heading_ok(p, i, pts):
    # The pose faces the next distinct point.
    q = p["orientation"]
    got = 2 * math.atan2(q["z"], q["w"])
    nxt = next((b for b in pts[i + 1:] if b != pts[i]), None)
    if nxt is None:
        return True
    want = math.atan2(nxt[1] - pts[i][1], nxt[0] - pts[i][0])
    d = (got - want + math.pi) % (2 * math.pi) - math.pi
    return abs(d) < 1e-4


# nav-path: nav_msgs/Path YAML
compile_to("nav-path", f"{outdir}/path.yaml")
with open(f"{outdir}/path.yaml") as f:
    doc = yaml.safe_load(f)
check(doc["header"]["frame_id"] == "map", "nav-path: header frame `map`")
poses = doc["poses"]
check(len(poses) == len(cells), "nav-path: one pose per cell")
pts = [(p["pose"]["position"]["x"], p["pose"]["position"]["y"]) for p in poses]
for i, (got, want) in enumerate(zip(pts, expected)):
    check(close(got, want), f"nav-path: pose {i} {got} is cell {cells[i]} at {want}")
    check(heading_ok(poses[i]["pose"], i, pts), f"nav-path: pose {i} faces along the path")

# waypoints: FollowWaypoints goal YAML; every stage goal and both ends are among them, and each
# waypoint is a route cell, in route order.
compile_to("waypoints", f"{outdir}/waypoints.yaml")
with open(f"{outdir}/waypoints.yaml") as f:
    wps = yaml.safe_load(f)["poses"]
wpts = [(p["pose"]["position"]["x"], p["pose"]["position"]["y"]) for p in wps]
idx = []
for w in wpts:
    start = idx[-1] if idx else 0
    k = next((j for j in range(start, len(expected)) if close(w, expected[j])), None)
    check(k is not None, f"waypoints: {w} lies on the route after the previous waypoint")
    idx.append(k)
check(idx[0] == 0 and idx[-1] == len(cells) - 1, "waypoints: start and end kept")
for e in ends:
    check(any(close(expected[min(e, len(cells) - 1)], w) for w in wpts),
          f"waypoints: stage goal at index {e} kept")
check(len(wps) < len(cells), "waypoints: thinner than the path")

# geojson
compile_to("geojson", f"{outdir}/route.geojson")
with open(f"{outdir}/route.geojson") as f:
    gj = json.load(f)
line = next(ft for ft in gj["features"] if ft["geometry"]["type"] == "LineString")
coords = line["geometry"]["coordinates"]
check(len(coords) == len(cells), "geojson: one vertex per cell")
for i, (got, want) in enumerate(zip(coords, expected)):
    check(close(got, want), f"geojson: vertex {i}")
stages = [ft for ft in gj["features"] if ft["properties"].get("kind") == "stage"]
check(len(stages) == len(ends), "geojson: one point per stage")
for ft, e in zip(stages, ends):
    check(close(ft["geometry"]["coordinates"], expected[min(e, len(cells) - 1)]),
          "geojson: stage point at its goal")

# mcap: container by `mcap`, messages by `rosbags` with its own ROS 2 definitions
compile_to("mcap", f"{outdir}/route.mcap")
ts = get_typestore(Stores.ROS2_HUMBLE)
topics = {}
with open(f"{outdir}/route.mcap", "rb") as f:
    reader = make_reader(f)
    check(reader.get_header().profile == "ros2", "mcap: ros2 profile")
    for schema, channel, message in reader.iter_messages():
        check(channel.message_encoding == "cdr" and schema.encoding == "ros2msg",
              f"mcap: {channel.topic} is ros2msg/cdr")
        topics[channel.topic] = ts.deserialize_cdr(message.data, schema.name)
check(set(topics) == {"/map", "/semantic_map", "/plan", "/route_stages"}, "mcap: topics")
grid = topics["/map"]
check(abs(grid.info.resolution - res) < 1e-6, "mcap: grid resolution")
check(close((grid.info.origin.position.x, grid.info.origin.position.y), (ox, oy), 1e-9),
      "mcap: grid origin")
n = grid.info.width
check(grid.info.height == n and len(grid.data) == n * n, "mcap: square grid data")
for c in cells:
    check(grid.data[c[0] * n + c[1]] == 0, f"mcap: route cell {c} is free in /map")
plan = topics["/plan"]
check(len(plan.poses) == len(cells), "mcap: /plan has one pose per cell")
for i, p in enumerate(plan.poses):
    got = (p.pose.position.x, p.pose.position.y)
    check(close(got, expected[i], 1e-9), f"mcap: /plan pose {i}")
marks = topics["/semantic_map"].markers
check(any(m.ns == "rooms" for m in marks) and any(m.ns == "objects" for m in marks),
      "mcap: rooms and objects markers")
check(len(topics["/route_stages"].markers) == len(ends), "mcap: one stage marker per stage")

print(f"robot round trip: {passed} passed, 0 failed")

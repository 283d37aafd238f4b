"""traversability.h5 read back with h5py the way mesh_navigation's mesh_map reads it (lvr2's
hdf5features::MeshIO: the mesh group's IO/CLASS attributes, every channel of geometry/, then
face_normals, vertex_normals and one vertex_attributes/<layer> per layer plugin), and every layer
checked against traversability.ply of the same export with a numpy oracle of the per-vertex rule.

Run by ctest with a Python that has h5py, numpy and PyYAML (Debian's /usr/bin/python3):
python3 -m unittest mesh_map_h5_test (TERRAMESH_BIN and TERRAMESH_SOURCE_DIR set).
"""

import os
import subprocess
import sys
import tempfile
import unittest

import h5py
import numpy as np
import yaml

SOURCE = os.environ.get("TERRAMESH_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(SOURCE, "scripts", "figures"))
import ply  # noqa: E402

BIN = os.environ.get("TERRAMESH_BIN", "terramesh")
ROBOT = os.path.join(SOURCE, "traversability", "robots", "small_wheeled.yaml")
# What mesh_map's layer plugins read (their configured names), then terramesh's own layers.
MESH_MAP_LAYERS = ["height_diff", "roughness", "steepness", "border", "clearance", "inflation", "cost",
                   "cost_allow_uncertain"]
OWN_LAYERS = ["lethal", "uncertain", "unknown", "contact", "evidence", "height_uncertainty_m", "reasons",
              "heading_fits"]
# lvr2's MeshBuffer channel types that HDF5 can hold (MultiChannelMap without bool and waveforms).
MESH_BUFFER_TYPES = {np.dtype(t) for t in ("i1", "u1", "i2", "u2", "i4", "u4", "i8", "u8", "f4", "f8")}
RANK_FREE, RANK_UNCERTAIN, RANK_LETHAL = 1, 2, 3


def run(*args):
    result = subprocess.run([str(a) for a in args], capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, f"{args}: {result.stderr}"
    return result


def read_mesh_map(test, path, part="mesh"):
    """The file as mesh_map's readMap() and its layers see it; asserts lvr2's checks on the way."""
    with h5py.File(path, "r") as h5:
        group = h5[part]
        # MeshIO::isMesh: the attribute datatypes must equal HighFive's std::string (H5Tequal).
        for name, expected in (("IO", "MeshIO"), ("CLASS", "MeshBuffer")):
            attribute = h5py.h5a.open(group.id, name.encode())
            kind = attribute.get_type()
            test.assertIsInstance(kind, h5py.h5t.TypeStringID, name)
            test.assertTrue(kind.is_variable_str(), name)
            test.assertEqual(kind.get_cset(), h5py.h5t.CSET_UTF8, name)
            test.assertEqual(attribute.shape, (), name)
            test.assertEqual(group.attrs[name], expected)
        # MeshIO::load: every dataset of geometry/ becomes a MeshBuffer channel (2-D, typed).
        geometry = {}
        for name, dataset in group["geometry"].items():
            test.assertIsInstance(dataset, h5py.Dataset, name)
            test.assertEqual(dataset.ndim, 2, name)
            test.assertIn(dataset.dtype, MESH_BUFFER_TYPES, name)
            geometry[name] = dataset[()]
        for name, dtype in (("vertices", np.float32), ("face_indices", np.uint32), ("vertex_normals", np.float32)):
            test.assertEqual(geometry[name].dtype, dtype, name)
            test.assertEqual(geometry[name].shape[1], 3, name)
        # getDenseAttributeMap<DenseFaceMap<Normal>>("face_normals"), then the vertex normals;
        # edge_distances (+ _idx) are left to mesh_map, which numbers edges itself.
        face_normals = group["face_attributes/face_normals"][()]
        vertex_normals = group["vertex_attributes/vertex_normals"][()]
        test.assertNotIn("edge_attributes", group)
        layers = {}
        for name in MESH_MAP_LAYERS + OWN_LAYERS:  # getDenseAttributeMap<DenseVertexMap<float>>(layer_name_)
            dataset = group["vertex_attributes/" + name]
            test.assertEqual(dataset.dtype, np.float32, name)
            test.assertEqual(dataset.shape, (geometry["vertices"].shape[0], 1), name)
            layers[name] = dataset[()][:, 0]
        version = h5["version"]
        test.assertEqual((version.shape, version.dtype, int(version[()])), ((), np.dtype("i4"), 1))
        return geometry, face_normals, vertex_normals, layers


def worst(faces, values, count, lowest=False):
    """A vertex takes the worst value of its faces, NaN face values skipped (NaN if none)."""
    result = np.full(count, np.nan, dtype=np.float32)
    for k in range(3):
        (np.fmin if lowest else np.fmax).at(result, faces[:, k], values.astype(np.float32))
    return result


def lvr2_normals(points, faces):
    """lvr2: face normal (v1 - v2) x (v1 - v3) normalised, vertex normal the normalised sum."""
    a, b, c = (points[faces[:, k]].astype(np.float64) for k in range(3))
    n = np.cross(a - b, a - c)
    length = np.linalg.norm(n, axis=1)
    n = np.where(length[:, None] > 0, n / np.where(length > 0, length, 1)[:, None], [0, 0, 1])
    sums = np.zeros((len(points), 3))
    for k in range(3):
        np.add.at(sums, faces[:, k], n)
    length = np.linalg.norm(sums, axis=1)
    vertex = np.where(length[:, None] > 0, sums / np.where(length > 0, length, 1)[:, None], [0, 0, 1])
    return n, vertex


class MeshMapCase(unittest.TestCase):
    def check_directory(self, out):
        """Every dataset of OUT/traversability.h5 against OUT/traversability.ply and the frame."""
        path = os.path.join(out, "traversability.h5")
        self.assertEqual(os.stat(path).st_mode & 0o777, 0o644)
        self.assertEqual([n for n in os.listdir(out) if n.startswith(".")], [])
        geometry, face_normals, vertex_normals, layers = read_mesh_map(self, path)
        elements = ply.read(os.path.join(out, "traversability.ply"))
        vertex, face = elements["vertex"], elements["face"]
        faces = face["vertex_indices"].astype(np.int64)
        n = vertex.count
        np.testing.assert_array_equal(geometry["face_indices"], faces)
        with open(os.path.join(out, "map_frame.yaml")) as handle:
            frame = yaml.safe_load(handle)
        axes = np.array([frame["plan_x"], frame["plan_y"], frame["up"]])
        p = np.column_stack([vertex[a] for a in "xyz"])
        expected = (p @ axes.T) * frame["metres_per_unit"]
        np.testing.assert_allclose(geometry["vertices"], expected, rtol=1e-6, atol=1e-5)
        face_n, vertex_n = lvr2_normals(geometry["vertices"], faces)
        np.testing.assert_allclose(face_normals, face_n, atol=1e-4)
        np.testing.assert_allclose(vertex_normals, vertex_n, atol=1e-4)
        np.testing.assert_array_equal(geometry["vertex_normals"], vertex_normals)

        lethal, unknown, uncertain = (face[k].astype(bool) for k in ("lethal", "unknown", "uncertain"))
        rank_face = np.where(lethal, RANK_LETHAL, np.where(uncertain, RANK_UNCERTAIN, np.where(unknown, 0, RANK_FREE)))
        rank = np.zeros(n, dtype=np.int64)
        for k in range(3):
            np.maximum.at(rank, faces[:, k], rank_face)
        # The PLY's per-vertex cost is the same rule (one routine): worst known face, lethal = 1.
        ply_cost = worst(faces, np.where(unknown, np.nan, np.where(lethal, 1.0, face["cost"])), n)
        np.testing.assert_array_equal(vertex["cost"], ply_cost)
        inf = np.float32(np.inf)
        np.testing.assert_array_equal(layers["cost"], np.where(rank == RANK_FREE, ply_cost, inf))
        allow = np.where((rank == RANK_FREE) | (rank == RANK_UNCERTAIN), ply_cost, inf)
        np.testing.assert_array_equal(layers["cost_allow_uncertain"], allow)
        for name, value in (("lethal", RANK_LETHAL), ("uncertain", RANK_UNCERTAIN), ("unknown", 0)):
            np.testing.assert_array_equal(layers[name], (rank == value).astype(np.float32), name)

        no_data_worst = lambda values: np.nan_to_num(worst(faces, values, n), nan=np.inf, posinf=np.inf)  # noqa: E731
        np.testing.assert_array_equal(layers["height_diff"], no_data_worst(face["step_m"]))
        np.testing.assert_array_equal(layers["roughness"], no_data_worst(face["roughness_m"]))
        steepness = no_data_worst(face["slope_deg"].astype(np.float32) * np.float32(np.pi / 180))
        np.testing.assert_allclose(layers["steepness"], steepness, rtol=1e-6)
        for name, lowest in (("contact", True), ("evidence", False), ("height_uncertainty_m", False)):
            np.testing.assert_array_equal(layers[name], worst(faces, face[name], n, lowest), name)
        # Why not free: every reason bit any face of the vertex has (NaN for a vertex without faces).
        bits = np.zeros(n, dtype=np.uint32)
        has_face = np.zeros(n, dtype=bool)
        for k in range(3):
            np.bitwise_or.at(bits, faces[:, k], face["reasons"].astype(np.uint32))
            has_face[faces[:, k]] = True
        np.testing.assert_array_equal(layers["reasons"], np.where(has_face, bits.astype(np.float32), np.nan))
        self.assertTrue((bits != 0).any(), "some vertex has a face that is not free")
        # The headings of travel every face of the vertex fits at.
        fits = np.full(n, np.uint32(0xFFFFFFFF), dtype=np.uint32)
        for k in range(3):
            np.bitwise_and.at(fits, faces[:, k], face["heading_fits"].astype(np.uint32))
        np.testing.assert_array_equal(layers["heading_fits"], np.where(has_face, fits.astype(np.float32), np.nan))
        self.assertTrue((face["heading_fits"] != 0).any(), "some face fits at a heading")
        # Unknown clearance (NaN) is no clearance for mesh_map's ClearanceLayer.
        clearance = worst(faces, np.nan_to_num(face["clearance_m"], nan=0.0, posinf=np.inf), n, lowest=True)
        np.testing.assert_array_equal(layers["clearance"], np.nan_to_num(clearance, nan=0.0, posinf=np.inf))

        border = np.nan_to_num(worst(faces, unknown.astype(np.float32), n), nan=1.0)
        edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
        unique, counts = np.unique(edges, axis=0, return_counts=True)
        border[unique[counts == 1].ravel()] = 1.0
        np.testing.assert_array_equal(layers["border"], border)

        with open(os.path.join(out, "robot.yaml")) as handle:
            robot = yaml.safe_load(handle)
        d = worst(faces, face["lethal_distance_m"], n, lowest=True).astype(np.float64)
        with np.errstate(invalid="ignore"):
            term = np.where(d <= robot["inflation_radius_m"],
                            np.where(d <= robot["inscribed_radius_m"], 1.0,
                                     np.exp(-robot["cost_scaling_factor"] * (d - robot["inscribed_radius_m"]))), 0.0)
        inflation = np.where(rank == RANK_LETHAL, np.inf, term).astype(np.float32)
        np.testing.assert_allclose(layers["inflation"], inflation, rtol=1e-6)
        for name in MESH_MAP_LAYERS:
            self.assertFalse(np.isnan(layers[name]).any(), f"{name}: mesh_map's layers are never NaN")
        return rank, layers


class TraverseTest(MeshMapCase):
    """`terramesh traverse` of a y-up mesh in half-metre units: a floor, a box, an unmeasured corner."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        side, spacing_m, scale = 41, 0.25, 0.5  # 10 m x 10 m, map unit = 0.5 m
        gx, gy = np.meshgrid(np.arange(side) * spacing_m, np.arange(side) * spacing_m)
        gx, gy = gx.ravel(), gy.ravel()
        box = (gx >= 4) & (gx <= 6) & (gy >= 4) & (gy <= 6)
        h = np.where(box, 0.6, 0.0)
        # y up: (x, y, z)_z-up -> (x, z, -y), a rotation (faces keep facing up).
        points = np.column_stack([gx, h, -gy]) / scale
        steiner = ((gx > 8.4) & (gy > 8.4)).astype(np.uint8)
        v = (np.arange(side - 1)[None, :] + side * np.arange(side - 1)[:, None]).ravel()
        faces = np.concatenate([np.column_stack([v, v + 1, v + side + 1]), np.column_stack([v, v + side + 1, v + side])])
        mesh = os.path.join(cls.tmp.name, "floor_box.ply")
        ply.write_binary(mesh, [("vertex", [("x", "double", points[:, 0]), ("y", "double", points[:, 1]),
                                            ("z", "double", points[:, 2]), ("steiner", "uchar", steiner)]),
                                ("face", [("vertex_indices", "list uchar uint", faces)])])
        cls.out = os.path.join(cls.tmp.name, "map")
        run(BIN, "traverse", mesh, "--robot", ROBOT, "-o", cls.out, "--up", "0,1,0", "--metres-per-unit", scale,
            "--no-geotiff", "--quiet")

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_every_layer_matches_the_ply(self):
        rank, layers = self.check_directory(self.out)
        self.assertGreater((rank == RANK_LETHAL).sum(), 0)
        self.assertGreater((rank == 0).sum(), 0)
        self.assertGreater(np.isfinite(layers["cost"]).sum(), 1000)

    def test_the_floor_is_z_up_in_metres(self):
        with h5py.File(os.path.join(self.out, "traversability.h5"), "r") as h5:
            vertices = h5["mesh/geometry/vertices"][()]
            normals = h5["mesh/vertex_attributes/vertex_normals"][()]
            steepness = h5["mesh/vertex_attributes/steepness"][()][:, 0]
        np.testing.assert_allclose(np.ptp(vertices, axis=0), [10, 10, 0.6], atol=1e-5)
        floor = np.abs(vertices[:, 2]) < 1e-6
        self.assertGreater(floor.sum(), 1000)
        flat = floor & (steepness < 1e-3)
        self.assertGreater(flat.sum(), 1000)
        np.testing.assert_allclose(normals[flat], np.tile([0, 0, 1], (flat.sum(), 1)), atol=1e-6)

    def test_no_mesh_map_h5_removes_it(self):
        out = os.path.join(self.tmp.name, "again")
        mesh = os.path.join(self.tmp.name, "floor_box.ply")
        args = ("traverse", mesh, "--robot", ROBOT, "-o", out, "--up", "0,1,0", "--no-geotiff", "--quiet")
        run(BIN, *args)
        self.assertTrue(os.path.exists(os.path.join(out, "traversability.h5")))
        run(BIN, *args, "--no-mesh-map-h5")
        self.assertFalse(os.path.exists(os.path.join(out, "traversability.h5")))


class MeshExportEveryTest(MeshMapCase):
    """`terramesh mesh --robot --export-every` on a generated street: the file a live map rewrites."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        d = cls.tmp.name
        run(BIN, "generate", "street", "--length-m", "40", "-o", f"{d}/scene", "--quiet")
        run(BIN, "mesh", f"{d}/scene/stream.tmstream", "-o", f"{d}/map", "--robot", ROBOT, "--export-every", "5",
            "--no-geotiff", "--quiet")
        cls.out = f"{d}/map"

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_every_layer_matches_the_ply(self):
        rank, layers = self.check_directory(self.out)
        self.assertGreater((rank == RANK_FREE).sum(), 100)
        self.assertGreater((rank == 0).sum(), 0)  # the Steiner faces closing the map
        self.assertGreater(np.isinf(layers["cost"]).sum(), 0)


if __name__ == "__main__":
    unittest.main()

"""Nothing lost (issue 11): `terramesh mesh` killed with SIGKILL and resumed from its last checkpoint gives the mesh
and traversability layers of the run that was never interrupted, byte for byte; SIGINT/SIGTERM finish the update in
progress, write a manifold mesh for the keyframes applied and exit with 130/143; truncated or corrupted checkpoints
are refused with exit code 2 and one line naming the file.

Run by ctest with: python3 -m unittest cli_checkpoint_test (TERRAMESH_BIN and TERRAMESH_SHARED_DIR set).
"""
import filecmp
import json
import os
import re
import shutil
import signal
import struct
import subprocess
import tempfile
import time
import unittest

BIN = os.environ["TERRAMESH_BIN"]
SHARED = os.environ["TERRAMESH_SHARED_DIR"]
CHECKER = os.path.join(SHARED, "tools", "check_mesh.py")
ROBOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "traversability", "robots",
                     "small_wheeled.yaml")
CHECKPOINT = "checkpoint.tmckpt"


def run(*args):
    return subprocess.run([BIN, *args], capture_output=True, text=True, timeout=900)


def check_mesh(path):
    result = subprocess.run(["python3", CHECKER, path, "--json"], capture_output=True, text=True, timeout=300)
    return result.returncode, json.loads(result.stdout) if result.stdout.strip() else None


PLY_TYPES = {"char": "b", "uchar": "B", "short": "h", "ushort": "H", "int": "i", "uint": "I", "float": "f",
             "double": "d", "int8": "b", "uint8": "B", "int32": "i", "uint32": "I", "float32": "f", "float64": "d"}


def read_binary_ply(path, skip=()):
    """{element: [records of raw property bytes]} of a binary little-endian PLY, without the properties in `skip`."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    elements = []
    for line in data[:end].decode("ascii").splitlines():
        words = line.split()
        if words[0] == "element":
            elements.append((words[1], int(words[2]), []))
        elif words[0] == "property":
            elements[-1][2].append((words[-1], words[1:-1]))
    at, result = end, {}
    for name, count, properties in elements:
        records = []
        for _ in range(count):
            record = []
            for prop, types in properties:
                start = at
                if types[0] == "list":
                    (n,) = struct.unpack_from("<" + PLY_TYPES[types[1]], data, at)
                    at += struct.calcsize(PLY_TYPES[types[1]])
                    at += n * struct.calcsize(PLY_TYPES[types[2]])
                else:
                    at += struct.calcsize(PLY_TYPES[types[0]])
                if prop not in skip:
                    record.append(data[start:at])  # bytes: NaN layers compare equal
            records.append(tuple(record))
        result[name] = records
    return result


def read_summary(out):
    with open(os.path.join(out, "summary.txt")) as f:
        return f.read()


class CheckpointCase(unittest.TestCase):
    """One generated street stream and its uninterrupted run, shared by the tests of a class."""

    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="terramesh_ckpt_")
        data = os.path.join(cls.dir, "data")
        result = run("generate", "street", "-o", data, "--quiet", "--length-m", "100",
                     "--loop-closure-drift-m", "1")
        assert result.returncode == 0, result.stderr
        cls.stream = os.path.join(data, "stream.tmstream")
        cls.reference = os.path.join(cls.dir, "reference")
        result = run("mesh", cls.stream, "-o", cls.reference, "--quiet", "--robot", ROBOT, "--snapshot-every", "1")
        assert result.returncode == 0, result.stderr

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    def out(self, name):
        path = os.path.join(self.dir, name)
        shutil.rmtree(path, ignore_errors=True)
        return path

    def start_until_checkpoint(self, out, *extra):
        """Starts `terramesh mesh` with checkpoints every 3 keyframes; returns it once the first one exists."""
        process = subprocess.Popen([BIN, "mesh", self.stream, "-o", out, "--quiet", "--robot", ROBOT,
                                    "--checkpoint-every", "3", *extra],
                                   stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        deadline = time.monotonic() + 600
        while not os.path.exists(os.path.join(out, CHECKPOINT)):
            self.assertIsNone(process.poll(), "the run ended before its first checkpoint")
            self.assertLess(time.monotonic(), deadline)
            time.sleep(0.005)
        self.assertIsNone(process.poll(), "the run must still be going when it is interrupted")
        return process

    def assert_same_outputs(self, out, reference):
        self.assertTrue(filecmp.cmp(os.path.join(out, "mesh.ply"), os.path.join(reference, "mesh.ply"), shallow=False),
                        "mesh.ply differs from the uninterrupted run's")
        # Every layer of every face identical, `rays` included: the resumed run recomputes the layers from the
        # surface, the uninterrupted one kept them current incrementally; both must count the same rays.
        resumed = read_binary_ply(os.path.join(out, "traversability.ply"))
        uninterrupted = read_binary_ply(os.path.join(reference, "traversability.ply"))
        self.assertEqual(resumed, uninterrupted, "traversability.ply differs from the uninterrupted run's")
        code, report = check_mesh(os.path.join(out, "mesh.ply"))
        self.assertEqual(code, 0, report)


class KillAndResumeTest(CheckpointCase):
    def test_sigkill_then_resume_gives_the_uninterrupted_mesh_and_layers(self):
        out = self.out("killed")
        process = self.start_until_checkpoint(out)
        process.send_signal(signal.SIGKILL)
        process.communicate(timeout=60)
        self.assertEqual(process.returncode, -signal.SIGKILL)
        self.assertFalse(os.path.exists(os.path.join(out, "mesh.ply")), "killed before the end")
        saved = os.path.join(self.dir, "killed.tmckpt")
        shutil.copy(os.path.join(out, CHECKPOINT), saved)

        result = run("mesh", self.stream, "-o", out, "--resume", saved, "--robot", ROBOT)
        self.assertEqual(result.returncode, 0, result.stderr)
        resumed_at = int(re.search(r"resumed: from .* at event (\d+)", read_summary(out)).group(1))
        self.assertGreater(resumed_at, 0)
        self.assertLess(resumed_at, len(os.listdir(os.path.join(self.reference, "snapshots"))))
        self.assert_same_outputs(out, self.reference)
        with open(os.path.join(out, "keyframes.csv")) as f, open(os.path.join(self.reference, "keyframes.csv")) as g:
            self.assertEqual(len(f.readlines()), len(g.readlines()), "keyframes.csv has a row per event")


class StopSignalTest(CheckpointCase):
    def assert_stopped(self, sig, code):
        out = self.out("stopped_%d" % sig)
        process = self.start_until_checkpoint(out)
        process.send_signal(sig)
        process.communicate(timeout=600)
        self.assertEqual(process.returncode, code)
        summary = read_summary(out)
        match = re.search(r"stopped: by signal %d after event (\d+) \((\d+) keyframes\); exit code %d" % (sig, code),
                          summary)
        self.assertIsNotNone(match, summary)
        event, keyframes = int(match.group(1)), int(match.group(2))
        self.assertEqual(re.search(r"^keyframes: (\d+)$", summary, re.M).group(1), str(keyframes))
        code_, report = check_mesh(os.path.join(out, "mesh.ply"))
        self.assertEqual(code_, 0, report)
        # The generated street sends only keyframes, so the run stopped right after its keyframe `keyframes`:
        # its mesh is the uninterrupted run's snapshot at that keyframe.
        self.assertEqual(event + 1, keyframes)
        snapshot = os.path.join(self.reference, "snapshots", "mesh_%06d.ply" % keyframes)
        self.assertTrue(filecmp.cmp(os.path.join(out, "mesh.ply"), snapshot, shallow=False))
        self.assertTrue(os.path.exists(os.path.join(out, "traversability.ply")))
        return out

    def test_sigint_finishes_the_update_writes_the_mesh_and_exits_130(self):
        out = self.assert_stopped(signal.SIGINT, 130)
        # The checkpoint written on the way out resumes to the uninterrupted result.
        result = run("mesh", self.stream, "-o", out, "--resume", os.path.join(out, CHECKPOINT), "--robot", ROBOT,
                     "--quiet")
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assert_same_outputs(out, self.reference)

    def test_sigterm_exits_143(self):
        self.assert_stopped(signal.SIGTERM, 143)


class BadCheckpointTest(CheckpointCase):
    def assert_refused(self, checkpoint, *fragments):
        out = self.out("refused")
        result = run("mesh", self.stream, "-o", out, "--resume", checkpoint)
        self.assertEqual(result.returncode, 2, result.stderr)
        lines = result.stderr.strip().splitlines()
        self.assertEqual(len(lines), 1, result.stderr)
        self.assertIn(checkpoint, lines[0])
        for fragment in fragments:
            self.assertIn(fragment, lines[0])
        self.assertFalse(os.path.exists(out), "nothing may be written for a bad checkpoint")

    def test_truncated_flipped_and_foreign_checkpoints_are_refused(self):
        out = self.out("source")
        process = self.start_until_checkpoint(out)
        process.send_signal(signal.SIGKILL)
        process.communicate(timeout=60)
        with open(os.path.join(out, CHECKPOINT), "rb") as f:
            good = f.read()
        cases = {
            "truncated.tmckpt": (good[:len(good) // 2], "truncated checkpoint"),
            "header_only.tmckpt": (good[:20], "truncated checkpoint"),
            "flipped.tmckpt": (good[:len(good) // 3] + bytes([good[len(good) // 3] ^ 0x10]) + good[len(good) // 3 + 1:],
                               "checksum mismatch"),
            "foreign.tmckpt": (b"ply\nformat ascii 1.0\n" + good[21:], "not a terramesh checkpoint"),
        }
        for name, (content, message) in cases.items():
            with self.subTest(name=name):
                path = os.path.join(self.dir, name)
                with open(path, "wb") as f:
                    f.write(content)
                self.assert_refused(path, message)

    def test_a_checkpoint_of_another_stream_is_refused(self):
        out = self.out("other_source")
        process = self.start_until_checkpoint(out)
        process.send_signal(signal.SIGKILL)
        process.communicate(timeout=60)
        other = os.path.join(self.dir, "other")
        self.assertEqual(run("generate", "street", "-o", other, "--quiet", "--length-m", "40").returncode, 0)
        result = run("mesh", os.path.join(other, "stream.tmstream"), "-o", self.out("refused"),
                     "--resume", os.path.join(out, CHECKPOINT))
        self.assertEqual(result.returncode, 2, result.stderr)
        self.assertIn("another input stream", result.stderr)


if __name__ == "__main__":
    unittest.main()

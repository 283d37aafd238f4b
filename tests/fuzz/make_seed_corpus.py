#!/usr/bin/env python3
"""Writes the seed corpora of tests/fuzz/corpus/<target>/ from small excerpts of the real files in
../shared/data (never whole files) plus hand-made seeds. Run once by hand; the seeds are checked
in, and regression inputs found by fuzzing are added beside them (named regression_*), which this
script leaves alone.

Usage: tests/fuzz/make_seed_corpus.py [SHARED_DIR]   (default: ../shared next to the checkout)
"""
import copy
import json
import os
import struct
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
SHARED = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, '..', '..', '..', 'shared')
DATA = os.path.join(SHARED, 'data')
CORPUS = os.path.join(HERE, 'corpus')
SEP = b'\n@@terramesh-fuzz-next-file@@\n'  # fuzz_support.h, kFileSeparator


def write(target, name, data):
    os.makedirs(os.path.join(CORPUS, target), exist_ok=True)
    if isinstance(data, str):
        data = data.encode()
    with open(os.path.join(CORPUS, target, name), 'wb') as f:
        f.write(data)


def slam_json():
    for src, tag in [('slam_data_version0.1_KITTI00_50frames.json', 'v01'),
                     ('non_incremental_slam_data_version0.2_KITTI00_200frames.json', 'v02')]:
        with open(os.path.join(DATA, 'kitti00_orbslam', src)) as f:
            doc = json.load(f)
        doc['views'] = doc['views'][:3]
        for view in doc['views']:
            view['observations'] = view['observations'][:4]
        write('slam_json', f'real_{tag}_excerpt.json', json.dumps(doc, indent=1))
        if tag == 'v02':
            doc['slam_data_version'] = '0.3'
            write('slam_json', 'real_v03_from_v02_excerpt.json', json.dumps(doc))
    write('slam_json', 'empty_views.json', '{"slam_data_version": "0.1", "views": []}')
    write('slam_json', 'minimal_v03.json', json.dumps({'slam_data_version': '0.3', 'views': [
        {'viewId': 0, 'extrinsic': {'rotation': [[1, 0, 0], [0, 1, 0], [0, 0, 1]], 'center': [0, 0, 0]},
         'observations': [{'pointId': 1, 'X': [0, 0, 1]}, {'pointId': 2, 'X': [1e308, -0.0, 1e-300]}]}]}))
    return doc


def tmstream(json_doc):
    """The 0.3 excerpt above in .tmstream form, plus removal events."""
    lines = ['# from the authors\' JSON excerpt (kitti00_orbslam)', 'terramesh_stream 1',
             'description fuzz seed', 'metres_per_unit 1']
    for view in json_doc['views']:
        c = view['extrinsic']['center']
        obs = view['observations']
        lines.append(f"keyframe {view['viewId']} {c[0]!r} {c[1]!r} {c[2]!r} 1 0 0 0 {len(obs)}")
        for o in obs:
            x = o['X']
            lines.append(f"{o['pointId']} {x[0]!r} {x[1]!r} {x[2]!r}")
    first = json_doc['views'][0]
    lines.append(f"remove_points 1 {first['observations'][0]['pointId']}")
    lines.append(f"remove_keyframe {first['viewId']}")
    write('tmstream', 'real_kitti00_excerpt.tmstream', '\n'.join(lines) + '\n')
    write('tmstream', 'minimal.tmstream', 'terramesh_stream 1\nkeyframe 0 0 0 0 1 0 0 0 1\n7 0 0 1\n')
    write('tmstream', 'truncated_keyframe.tmstream', 'terramesh_stream 1\nkeyframe 0 0 0 0 1 0 0 0 3\n7 0 0 1\n')


def openmvg():
    with open(os.path.join(DATA, 'openmvg_dinoring', 'sfm_data.json')) as f:
        doc = json.load(f)
    doc['views'] = doc['views'][:3]
    doc['intrinsics'] = doc['intrinsics'][:1]
    doc['extrinsics'] = doc['extrinsics'][:3]
    kept_views = {v['key'] for v in doc['views']}
    structure = []
    for point in doc['structure']:
        observations = [o for o in point['value']['observations'] if o['key'] in kept_views][:3]
        if observations:
            point = copy.deepcopy(point)
            point['value']['observations'] = observations
            structure.append(point)
        if len(structure) >= 6:
            break
    doc['structure'] = structure
    write('openmvg', 'real_dinoring_excerpt.json', json.dumps(doc, indent=1))
    doc['structure'] = []
    write('openmvg', 'real_dinoring_no_structure.json', json.dumps(doc))
    write('openmvg', 'empty.json',
          '{"sfm_data_version": "0.3", "views": [], "intrinsics": [], "extrinsics": [], "structure": []}')


def colmap_excerpt(images_kept=3, points2d_kept=25):
    """A consistent small COLMAP model cut from the real text model: the first images, their
    first 2D points, the 3D points seen there (tracks cut to the kept observations)."""
    model = os.path.join(DATA, 'colmap_statue_of_liberty', 'txt_model_40img')
    cameras = []
    with open(os.path.join(model, 'cameras.txt')) as f:
        for line in f:
            if line.strip() and not line.startswith('#'):
                w = line.split()
                cameras.append((int(w[0]), w[1], int(w[2]), int(w[3]), [float(p) for p in w[4:]]))
    with open(os.path.join(model, 'images.txt')) as f:
        data_lines = [l for l in f if not l.startswith('#')]
    images = []
    for i in range(images_kept):
        head, pts = data_lines[2 * i].split(), data_lines[2 * i + 1].split()
        points2d = [(float(pts[k]), float(pts[k + 1]), int(pts[k + 2])) for k in range(0, len(pts), 3)]
        images.append([int(head[0]), [float(v) for v in head[1:8]], int(head[8]), head[9],
                       points2d[:points2d_kept]])
    observed = {(im[0], idx) for im in images for idx in range(len(im[4]))}
    points = []
    with open(os.path.join(model, 'points3D.txt')) as f:
        for line in f:
            if line.startswith('#') or not line.strip():
                continue
            w = line.split()
            track = [(int(w[k]), int(w[k + 1])) for k in range(8, len(w), 2)]
            track = [t for t in track if t in observed]
            if track:
                points.append((int(w[0]), [float(v) for v in w[1:4]], [int(v) for v in w[4:7]],
                               float(w[7]), track))
    in_track = {(t, p[0]) for p in points for t in p[4]}
    for im in images:
        im[4] = [(x, y, pid if ((im[0], idx), pid) in in_track else -1)
                 for idx, (x, y, pid) in enumerate(im[4])]
    return cameras, images, points


MODEL_IDS = {'SIMPLE_PINHOLE': 0, 'PINHOLE': 1, 'SIMPLE_RADIAL': 2, 'RADIAL': 3, 'OPENCV': 4}


def colmap(cameras, images, points):
    cam_txt = ''.join(f"{c[0]} {c[1]} {c[2]} {c[3]} {' '.join(repr(p) for p in c[4])}\n" for c in cameras)
    img_txt = ''
    for im in images:
        img_txt += f"{im[0]} {' '.join(repr(v) for v in im[1])} {im[2]} {im[3]}\n"
        img_txt += ' '.join(f'{x!r} {y!r} {pid}' for x, y, pid in im[4]) + '\n'
    pts_txt = ''.join(f"{p[0]} {' '.join(repr(v) for v in p[1])} {' '.join(map(str, p[2]))} {p[3]!r} "
                      f"{' '.join(f'{a} {b}' for a, b in p[4])}\n" for p in points)
    write('colmap_text', 'real_statue_excerpt.txt', SEP.join(s.encode() for s in (cam_txt, img_txt, pts_txt)))
    write('colmap_text', 'no_points.txt', SEP.join(s.encode() for s in (cam_txt, img_txt.split('\n')[0] + '\n\n', '')))
    write('colmap_text', 'comments_only.txt', SEP.join([b'# cameras\n', b'# images\n', b'# points\n']))

    cam_bin = struct.pack('<Q', len(cameras))
    for c in cameras:
        cam_bin += struct.pack('<IiQQ', c[0], MODEL_IDS[c[1]], c[2], c[3]) + struct.pack(f'<{len(c[4])}d', *c[4])
    img_bin = struct.pack('<Q', len(images))
    for im in images:
        img_bin += struct.pack('<I7dI', im[0], *im[1], im[2]) + im[3].encode() + b'\0'
        img_bin += struct.pack('<Q', len(im[4])) + b''.join(struct.pack('<ddq', *p) for p in im[4])
    pts_bin = struct.pack('<Q', len(points))
    for p in points:
        pts_bin += struct.pack('<Q3d3Bd', p[0], *p[1], *p[2], p[3]) + struct.pack('<Q', len(p[4]))
        pts_bin += b''.join(struct.pack('<II', a, b) for a, b in p[4])
    write('colmap_bin', 'real_statue_excerpt.bin', SEP.join([cam_bin, img_bin, pts_bin]))
    write('colmap_bin', 'empty_model.bin', SEP.join([struct.pack('<Q', 0)] * 3))
    write('colmap_bin', 'huge_count.bin', SEP.join([struct.pack('<Q', 1 << 60), img_bin, pts_bin]))


def bundler(cameras, images, points):
    """The COLMAP excerpt as a Bundler v0.3 file (R, t as stored; y flipped in the 2D points)."""
    f = cameras[0][4][0]
    out = ['# Bundle file v0.3', f'{len(images)} {len(points)}']
    index = {im[0]: i for i, im in enumerate(images)}
    for im in images:
        qw, qx, qy, qz, tx, ty, tz = im[1]
        rot = [[1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qw * qz), 2 * (qx * qz + qw * qy)],
               [2 * (qx * qy + qw * qz), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qw * qx)],
               [2 * (qx * qz - qw * qy), 2 * (qy * qz + qw * qx), 1 - 2 * (qx * qx + qy * qy)]]
        out.append(f'{f!r} 0 0')
        out += [' '.join(repr(v) for v in row) for row in rot]
        out.append(f'{tx!r} {ty!r} {tz!r}')
    for p in points:
        out.append(' '.join(repr(v) for v in p[1]))
        out.append(' '.join(map(str, p[2])))
        views = []
        for image_id, idx in p[4]:
            x, y, _ = images[index[image_id]][4][idx]
            views.append(f'{index[image_id]} {idx} {x - 400!r} {600 - y!r}')
        out.append(f'{len(views)} ' + ' '.join(views))
    bundle = '\n'.join(out) + '\n'
    listing = ''.join(f'{im[3]}\n' for im in images)
    write('bundler', 'real_statue_excerpt_with_list.out', bundle.encode() + SEP + listing.encode())
    write('bundler', 'real_statue_excerpt.out', bundle)
    write('bundler', 'unreconstructed_camera.out', '# Bundle file v0.3\n1 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n0 0 0\n')


def kitti():
    with open(os.path.join(DATA, 'kitti00_lidar', 'velodyne', '000001.bin'), 'rb') as f:
        write('kitti_bin', 'real_000001_first64.bin', f.read(64 * 16))
    write('kitti_bin', 'one_return.bin', struct.pack('<4f', 1.0, 2.0, 3.0, 0.5))
    write('kitti_bin', 'nan_return.bin', struct.pack('<4f', float('nan'), 2.0, float('inf'), 0.5))
    write('kitti_bin', 'partial_record.bin', struct.pack('<3f', 1.0, 2.0, 3.0))
    with open(os.path.join(DATA, 'kitti00_lidar', 'calib.txt')) as f:
        write('kitti_text', 'real_calib.txt', f.read())
    with open(os.path.join(DATA, 'kitti_poses', '00.txt')) as f:
        write('kitti_text', 'real_poses00_first5.txt', ''.join(f.readlines()[:5]))
    with open(os.path.join(DATA, 'kitti00_lidar', 'times.txt')) as f:
        write('kitti_text', 'real_times_first8.txt', ''.join(f.readlines()[:8]))
    write('kitti_text', 'tr_only.txt', 'Tr: 1 0 0 0 0 1 0 0 0 0 1 0\n')


def tum():
    """KITTI 00's first poses and times as a TUM trajectory (quaternion from the rotation)."""
    with open(os.path.join(DATA, 'kitti_poses', '00.txt')) as f:
        poses = [list(map(float, l.split())) for l in f.readlines()[:6]]
    with open(os.path.join(DATA, 'kitti00_lidar', 'times.txt')) as f:
        times = [float(l) for l in f.readlines()[:6]]
    lines = ['# timestamp tx ty tz qx qy qz qw (KITTI 00, first frames)']
    for t, p in zip(times, poses):
        r = [[p[0], p[1], p[2]], [p[4], p[5], p[6]], [p[8], p[9], p[10]]]
        qw = max(0.0, 1 + r[0][0] + r[1][1] + r[2][2]) ** 0.5 / 2
        qx = (r[2][1] - r[1][2]) / (4 * qw)
        qy = (r[0][2] - r[2][0]) / (4 * qw)
        qz = (r[1][0] - r[0][1]) / (4 * qw)
        lines.append(f'{t!r} {p[3]!r} {p[7]!r} {p[11]!r} {qx!r} {qy!r} {qz!r} {qw!r}')
    write('tum', 'real_kitti00_first6.txt', '\n'.join(lines) + '\n')
    write('tum', 'one_pose.txt', '0 0 0 0 0 0 0 1\n')
    write('tum', 'unnormalised.txt', '1.5 1e300 -1e300 0 0 0 0 2\n')


def meshes():
    """Inputs of `traverse` (mesher::readMesh) and of the generic PLY reader."""
    with open(os.path.join(DATA, 'kitti00_lidar', 'lidar_gt_frames01-10_cam0world_vox10cm.ply'), 'rb') as f:
        raw = f.read(4096)
    header_end = raw.index(b'end_header\n') + len(b'end_header\n')
    header = raw[:header_end].replace(b'element vertex 359474', b'element vertex 40')
    lidar = header + raw[header_end:header_end + 40 * 16]
    write('ply', 'real_lidar_gt_first40.ply', lidar)
    tri_ascii = ('ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n'
                 'property float z\nproperty uchar steiner\nelement face 2\n'
                 'property list uchar int vertex_indices\nend_header\n'
                 '0 0 0 0\n1 0 0 0\n1 1 0 1\n0 1 0.5 0\n3 0 1 2\n3 0 2 3\n')
    header = ('ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty double x\n'
              'property double y\nproperty double z\nelement face 1\n'
              'property list uchar uint vertex_indices\nend_header\n').encode()
    tri_big = header + struct.pack('>9d', 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack('>B3I', 3, 0, 1, 2)
    header_le = header.replace(b'binary_big_endian', b'binary_little_endian')
    tri_little = header_le + struct.pack('<9d', 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack('<B3I', 3, 0, 1, 2)
    for target in ('ply', 'traverse_mesh'):
        write(target, 'two_triangles_ascii.ply', tri_ascii)
        write(target, 'triangle_big_endian.ply', tri_big)
        write(target, 'triangle_little_endian.ply', tri_little)
    write('traverse_mesh', 'real_lidar_gt_first40.ply', lidar)
    with open(os.path.join(DATA, 'kitti00_orbslam', 'reference_meshes',
                           'KITTI_200frames_D=100_Step=40_ManifoldFinal.off')) as f:
        lines = f.read().split('\n')
    vertex_count, face_count = int(lines[1].split()[0]), int(lines[1].split()[1])
    faces = [l for l in lines[2 + vertex_count:2 + vertex_count + face_count]
             if l.split() and all(int(i) < 200 for i in l.split()[1:])][:30]
    off = ['OFF', f'200 {len(faces)} 0'] + lines[2:202] + faces
    write('traverse_mesh', 'real_reference_off_excerpt.off', '\n'.join(off) + '\n')
    write('traverse_mesh', 'square.obj', 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1/1/1 3//2 -1\n')


def robots():
    folder = os.path.join(HERE, '..', '..', 'traversability', 'robots')
    for name in sorted(os.listdir(folder)):
        with open(os.path.join(folder, name)) as f:
            write('robot_yaml', name, f.read())
    write('robot_yaml', 'rectangle_gravity.yaml',
          'name: box\nfootprint: {length_m: 1.2, width_m: 0.8}\ngravity: [0, 0, -1]\n'
          'weights: {slope: 1, step: 0, roughness: 0, contact: 0, inflation: 0}\n')


def maps():
    """traversability.ply of a map directory (traversability/io/src/layered_ply.cpp): a square of two
    faces, one free and one uncertain, in ASCII and in binary as terramesh writes it."""
    floats = ['slope_deg', 'step_m', 'roughness_m', 'contact', 'contact_best', 'clearance_m', 'lethal_distance_m',
              'height_uncertainty_m']
    header = ['ply', 'format {}', 'element vertex 4', 'property double x', 'property double y', 'property double z',
              'property uchar steiner', 'property float cost', 'element face 2',
              'property list uchar uint vertex_indices', 'property float cost', 'property uchar lethal',
              'property uchar unknown', 'property uchar uncertain'] + [f'property float {n}' for n in floats] + [
              'property uchar evidence', 'property uint rays', 'property ushort reasons',
              'property uint front_crossings', 'property uchar steiner', 'end_header']
    vertices = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
    # (indices, cost, lethal, unknown, uncertain, 8 floats, evidence, rays, reasons, front_crossings, steiner)
    faces = [((0, 1, 2), 0.2, 0, 0, 0, [1.0, 0.01, 0.0, 1.0, 1.0, float('inf'), float('inf'), 0.04], 0, 7, 0, 5, 0),
             ((0, 2, 3), 0.9, 0, 0, 1, [2.0, 0.2, 0.01, 0.8, 0.9, float('inf'), 1.5, 0.3], 2, 4, 80, 0, 0)]
    text = '\n'.join(header).format('ascii 1.0') + '\n'
    text += ''.join(f'{x} {y} {z} 0 0.2\n' for x, y, z in vertices)
    for f in faces:
        values = [3, *f[0], f[1], f[2], f[3], f[4], *f[5], f[6], f[7], f[8], f[9], f[10]]
        text += ' '.join(str(v) for v in values) + '\n'
    write('map_ply', 'square_ascii.ply', text)
    binary = ('\n'.join(header).format('binary_little_endian 1.0') + '\n').encode()
    for x, y, z in vertices:
        binary += struct.pack('<dddBf', x, y, z, 0, 0.2)
    for f in faces:
        binary += struct.pack('<B3If3B8fBIHIB', 3, *f[0], f[1], f[2], f[3], f[4], *f[5], f[6], f[7], f[8], f[9], f[10])
    write('map_ply', 'square_binary.ply', binary)


def main():
    doc = slam_json()
    tmstream(doc)
    openmvg()
    model = colmap_excerpt()
    colmap(*model)
    bundler(*model)
    kitti()
    tum()
    meshes()
    robots()
    maps()


if __name__ == '__main__':
    main()

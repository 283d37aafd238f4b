// What is drawn over the map: camera trajectory, SLAM points, planned paths, OctoMap voxels.
import * as THREE from 'three';

/** Camera centres of trajectory.csv rows with keyframe <= k; a corrected keyframe keeps its latest pose. */
export function trajectoryPositions(csv, k, origin) {
  const c = csv.columns;
  const latest = new Map();
  for (let r = 0; r < csv.rows; ++r) {
    if (c.keyframe[r] > k) break;
    latest.set(c.id[r], [c.x[r] - origin[0], c.y[r] - origin[1], c.z[r] - origin[2]]);
  }
  return [...latest.values()];
}

export class Trajectory {
  constructor(csv, origin) {
    this.csv = csv;
    this.origin = origin;
    const n = csv.rows;
    this.geometry = new THREE.BufferGeometry();
    this.geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(3 * Math.max(1, n)), 3));
    this.object = new THREE.Group();
    this.object.add(new THREE.Line(this.geometry, new THREE.LineBasicMaterial({ color: 0xffd400 })));
    this.object.add(new THREE.Points(this.geometry, new THREE.PointsMaterial({ color: 0xffd400, size: 5, sizeAttenuation: false })));
    this.object.name = 'trajectory';
  }

  /** Shows the trajectory up to keyframe k. */
  setKeyframe(k) {
    const positions = trajectoryPositions(this.csv, k, this.origin);
    const attribute = this.geometry.attributes.position;
    positions.forEach((p, i) => attribute.setXYZ(i, p[0], p[1], p[2]));
    attribute.needsUpdate = true;
    this.geometry.setDrawRange(0, positions.length);
    this.geometry.computeBoundingSphere();
  }
}

export class SlamPoints {
  constructor(data) {
    this.data = data;
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(data.positions, 3));
    this.object = new THREE.Points(geometry, new THREE.PointsMaterial({ color: 0x7fd8ff, size: 2, sizeAttenuation: false }));
    this.object.name = 'slam-points';
  }

  /** points.ply is in order of first sighting, so the points seen by keyframe k are a prefix. */
  setKeyframe(k) {
    const first = this.data.firstKeyframe;
    let n = this.data.count;
    if (first) {
      let lo = 0, hi = first.length;
      while (lo < hi) { const mid = (lo + hi) >> 1; if (first[mid] <= k) lo = mid + 1; else hi = mid; }
      n = lo;
    }
    this.object.geometry.setDrawRange(0, n);
  }
}

const PATH_COLOURS = [0x00e5ff, 0xffffff, 0xff8c00, 0x7cfc00];  // not magenta: uncertain faces

/** A path*.csv (x, y, z, ...) as a tube lifted a little along up, so it stays visible on the mesh. */
export function pathObject(csv, origin, up, radius, index) {
  const c = csv.columns;
  const lift = new THREE.Vector3(...up).normalize().multiplyScalar(2 * radius);
  const points = [];
  for (let r = 0; r < csv.rows; ++r) {
    const p = new THREE.Vector3(c.x[r] - origin[0], c.y[r] - origin[1], c.z[r] - origin[2]).add(lift);
    if (points.length === 0 || p.distanceToSquared(points[points.length - 1]) > 1e-12) points.push(p);
  }
  const colour = PATH_COLOURS[index % PATH_COLOURS.length];
  const group = new THREE.Group();
  group.name = `path-${index}`;
  if (points.length >= 2) {
    const curve = new THREE.CurvePath();
    for (let i = 1; i < points.length; ++i) curve.add(new THREE.LineCurve3(points[i - 1], points[i]));
    const tube = new THREE.TubeGeometry(curve, Math.min(4000, 4 * points.length), radius, 6, false);
    group.add(new THREE.Mesh(tube, new THREE.MeshBasicMaterial({ color: colour })));
  }
  const ends = new THREE.SphereGeometry(3 * radius, 12, 8);
  for (const p of [points[0], points[points.length - 1]]) {
    if (!p) continue;
    const marker = new THREE.Mesh(ends, new THREE.MeshBasicMaterial({ color: colour }));
    marker.position.copy(p);
    group.add(marker);
  }
  return group;
}

/**
 * OctoMap occupied voxels (voxels.bin) as one instanced box mesh. voxels.bin is in the octree's
 * frame G (planning::OctomapBaseline): metres, +z along up, R_G_W the shortest rotation taking up
 * onto +z. The object's matrix maps G back to the mesh frame: p_W = R_G_W^T p_G / metres_per_unit.
 */
export function voxelObject(voxels, origin, up, metresPerUnit) {
  const box = new THREE.BoxGeometry(1, 1, 1);
  // Unlit and mostly opaque: voxels of 0.1-0.2 m are a few pixels wide on a street-sized map.
  const material = new THREE.MeshBasicMaterial({ color: 0xff9933, transparent: true, opacity: 0.8, depthWrite: false });
  const mesh = new THREE.InstancedMesh(box, material, Math.max(1, voxels.count));
  const m = new THREE.Matrix4();
  const d = voxels.data;
  for (let i = 0; i < voxels.count; ++i) {
    const s = d[4 * i + 3];
    m.makeScale(s, s, s).setPosition(d[4 * i], d[4 * i + 1], d[4 * i + 2]);
    mesh.setMatrixAt(i, m);
  }
  mesh.count = voxels.count;
  mesh.instanceMatrix.needsUpdate = true;
  mesh.computeBoundingSphere();
  const q_G_W = new THREE.Quaternion().setFromUnitVectors(new THREE.Vector3(...up).normalize(), new THREE.Vector3(0, 0, 1));
  const unit = 1 / (metresPerUnit > 0 ? metresPerUnit : 1);
  mesh.matrixAutoUpdate = false;
  mesh.matrix.compose(new THREE.Vector3(-origin[0], -origin[1], -origin[2]), q_G_W.invert(), new THREE.Vector3(unit, unit, unit));
  mesh.name = 'voxels';
  return mesh;
}

// An inspection in 3D (three.js, vendored in static/vendor/three): the mission's structures
// extruded from their footprints, the points of interest seen (green) and not seen (red), the
// path, and each viewpoint with the way its camera looks. Drag to turn, scroll to zoom.

import * as THREE from 'three';
import { OrbitControls } from '../vendor/three/OrbitControls.js';
import { $ } from './api.js';
import { state } from './map.js';

let view = null; // { renderer, controls }

export function hide3d() {
  $('view3d').hidden = true;
  $('view3d-legend').hidden = true;
  if (view) {
    view.controls.dispose();
    view.renderer.dispose();
    view.renderer.domElement.remove();
    view = null;
  }
  state.view3d = null;
}

const colours = { structure: 0xb0bec5, seen: 0x2e7d32, unseen: 0xc62828, path: 0x6a1b9a, viewpoint: 0xef6c00 };

/** A structure's footprint as a three.js shape in local metres. */
function shapeOf(layer, xy) {
  if (layer instanceof L.Circle) {
    const c = layer.getLatLng();
    const shape = new THREE.Shape();
    shape.absarc(...xy(c.lng, c.lat), layer.getRadius(), 0, 2 * Math.PI, false);
    return shape;
  }
  const rings = layer.getLatLngs();
  const [outer, ...holes] = Array.isArray(rings[0]) ? rings : [rings];
  const points = (ring) => ring.map((p) => new THREE.Vector2(...xy(p.lng, p.lat)));
  const shape = new THREE.Shape(points(outer));
  holes.forEach((h) => shape.holes.push(new THREE.Path(points(h))));
  return shape;
}

export function show3d(fc) {
  hide3d();
  const el = $('view3d');
  el.hidden = false;
  $('view3d-legend').hidden = false;
  const structures = state.structures.getLayers();
  const centre = structures.length ? state.structures.getBounds().getCenter() : L.latLng(0, 0);
  // east, north and up in metres around the structures (a plane is exact enough to look at)
  const k = Math.cos((centre.lat * Math.PI) / 180);
  const xy = (lng, lat) => [(lng - centre.lng) * 111320 * k, (lat - centre.lat) * 110574];
  const at = ([lng, lat, z]) => new THREE.Vector3(...xy(lng, lat), z || 0);

  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0xf4f7f5);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x8d9c90, 2.5));
  const sun = new THREE.DirectionalLight(0xffffff, 1.2);
  sun.position.set(30, -40, 60);
  scene.add(sun);
  const counts = { structures: 0, seen: 0, unseen: 0, viewpoints: 0, legs: 0 };
  // the view frames the structures and the viewpoints, not the way from and back to the home
  const focus = new THREE.Box3();
  const watch = (object) => { focus.expandByObject(object); return object; };

  // models (their faces show through the points seen and not seen) are not extruded
  for (const layer of structures.filter((l) => !l.cpFeature)) {
    const geometry = new THREE.ExtrudeGeometry(shapeOf(layer, xy), { depth: layer.cpHeight, bevelEnabled: false });
    const mesh = new THREE.Mesh(geometry, new THREE.MeshLambertMaterial({ color: colours.structure }));
    mesh.position.z = layer.cpBase || 0;
    scene.add(watch(mesh));
    counts.structures += 1;
  }
  for (const kind of ['seen', 'unseen']) {
    const f = fc.features.find((g) => g.properties.kind === kind);
    if (!f || !f.geometry.coordinates.length) continue;
    const geometry = new THREE.BufferGeometry().setFromPoints(f.geometry.coordinates.map(at));
    scene.add(new THREE.Points(geometry, new THREE.PointsMaterial({ color: colours[kind], size: 0.4 })));
    counts[kind] = f.geometry.coordinates.length;
  }
  for (const f of fc.features.filter((g) => g.geometry.type === 'LineString')) {
    const geometry = new THREE.BufferGeometry().setFromPoints(f.geometry.coordinates.map(at));
    scene.add(new THREE.Line(geometry, new THREE.LineBasicMaterial({ color: colours.path })));
    counts.legs += 1;
  }
  for (const f of fc.features.filter((g) => g.properties.kind === 'viewpoint')) {
    const p = at(f.geometry.coordinates);
    const dot = new THREE.Mesh(new THREE.SphereGeometry(0.35, 12, 8), new THREE.MeshBasicMaterial({ color: colours.viewpoint }));
    dot.position.copy(p);
    scene.add(watch(dot));
    // the camera's axis: compass yaw to a math angle, and the gimbal's pitch
    const yaw = ((90 - f.properties.yaw_deg) * Math.PI) / 180;
    const pitch = (f.properties.gimbal_pitch_deg * Math.PI) / 180;
    const look = new THREE.Vector3(Math.cos(pitch) * Math.cos(yaw), Math.cos(pitch) * Math.sin(yaw), Math.sin(pitch)).multiplyScalar(2.5);
    scene.add(new THREE.Line(new THREE.BufferGeometry().setFromPoints([p, p.clone().add(look)]), new THREE.LineBasicMaterial({ color: colours.viewpoint })));
    counts.viewpoints += 1;
  }

  const box = focus.isEmpty() ? new THREE.Box3().setFromObject(scene) : focus;
  const size = box.getSize(new THREE.Vector3()).length() || 50;
  const middle = box.getCenter(new THREE.Vector3());
  const camera = new THREE.PerspectiveCamera(45, el.clientWidth / el.clientHeight, 0.1, size * 20);
  camera.up.set(0, 0, 1);
  camera.position.set(middle.x + size * 0.55, middle.y - size * 0.8, middle.z + size * 0.5);
  let renderer;
  try {
    renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  } catch (e) {
    el.textContent = `this browser cannot draw in 3D (${e.message})`;
    state.view3d = { ...counts, drawn: false };
    return;
  }
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  renderer.setSize(el.clientWidth, el.clientHeight);
  el.appendChild(renderer.domElement);
  const controls = new OrbitControls(camera, renderer.domElement);
  controls.target.copy(middle);
  controls.update();
  const render = () => renderer.render(scene, camera);
  controls.addEventListener('change', render);
  render();
  view = { renderer, controls };
  state.view3d = { ...counts, drawn: true };
}

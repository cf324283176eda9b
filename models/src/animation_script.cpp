// models/src/animation_script.cpp: the viewer script and style of an animation page
// (animation_page.cpp). The script reads the motion's JSON, builds the shapes (three.js r111),
// and plays the frames, interpolating positions linearly and orientations by slerp. The URL's
// hash sets it up (docs/robots.md): t=SECONDS (start there, paused), speed=X, play=0,
// cam=EX,EY,EZ,TX,TY,TZ (the camera's position and target, world frame, m), fov=DEGREES,
// flat=1 (unlit colours, no grid: the browser tests), ui=0 (no panel, bar or warnings: a
// snapshot), ghosts=T1,T2,... (the robot also drawn at those times, fainter: a strip of poses).
// With contact, the ground (the grid on it) and the static boxes are drawn, and each frame's
// contact points as red dots.
// When the first frame is drawn, the body gets data-ready="1".
namespace varsym::models::animation_detail {

const char* viewer_style() {
    return R"css(
html, body { margin: 0; height: 100%; overflow: hidden; background: #f4f5f7;
  font: 13px/1.35 system-ui, sans-serif; color: #222; }
#view { position: absolute; inset: 0; }
#panel { position: absolute; top: 8px; left: 8px; background: rgba(255,255,255,0.85);
  padding: 6px 10px; border-radius: 6px; max-height: 70%; overflow: auto; }
#title { font-weight: 600; }
#note { font-size: 85%; color: #555; max-width: 22em; }
#time { font-variant-numeric: tabular-nums; margin: 2px 0 4px; }
#joints td { padding: 0 6px 0 0; font-variant-numeric: tabular-nums; }
#joints td.v { text-align: right; }
#warnings { position: absolute; top: 8px; right: 8px; max-width: 45%; background: #fff3cd;
  border: 1px solid #e0c36a; padding: 6px 10px; border-radius: 6px; max-height: 40%;
  overflow: auto; font-size: 12px; word-break: break-all; }
#warnings:empty { display: none; }
#bar { position: absolute; left: 0; right: 0; bottom: 0; display: flex; gap: 10px;
  align-items: center; padding: 8px; background: rgba(255,255,255,0.85); }
#slider { flex: 1; }
body.bare #panel, body.bare #bar, body.bare #warnings { display: none; }
)css";
}

const char* viewer_script() {
    return R"js(
(function () {
  'use strict';
  const data = JSON.parse(document.getElementById('varsym-motion').textContent);
  function bytes(b64) {
    const s = atob(b64), u = new Uint8Array(s.length);
    for (let i = 0; i < s.length; i++) u[i] = s.charCodeAt(i);
    return u;
  }
  const T = new Float64Array(bytes(data.t).buffer);
  const P = new Float32Array(bytes(data.poses).buffer);
  const Q = new Float32Array(bytes(data.q).buffer);
  const nf = T.length, nb = data.bodies, nq = data.names.length;
  const hash = new URLSearchParams(location.hash.slice(1));
  const flat = hash.get('flat') === '1';
  if (hash.get('ui') === '0') document.body.classList.add('bare');

  // The warnings: the first shown, the others behind a click.
  const warn = document.getElementById('warnings');
  data.warnings.forEach(function (w, i) {
    const d = document.createElement('div');
    d.textContent = '\u26a0 ' + w;
    if (i === 1 && data.warnings.length > 2) {
      const more = document.createElement('details');
      const summary = document.createElement('summary');
      summary.textContent = (data.warnings.length - 1) + ' more warnings';
      more.appendChild(summary);
      warn.appendChild(more);
    }
    (warn.lastChild && warn.lastChild.tagName === 'DETAILS' ? warn.lastChild : warn).appendChild(d);
  });

  const renderer = new THREE.WebGLRenderer({antialias: !flat, preserveDrawingBuffer: true});
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  renderer.setSize(window.innerWidth, window.innerHeight);
  document.getElementById('view').appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0xf4f5f7);
  const R = data.radius, C = new THREE.Vector3().fromArray(data.centre);
  const camera = new THREE.PerspectiveCamera(Number(hash.get('fov') || 40),
      window.innerWidth / window.innerHeight, R / 100, R * 200);
  camera.up.set(0, 0, 1);
  const controls = new THREE.OrbitControls(camera, renderer.domElement);
  function home() {
    const cam = (hash.get('cam') || '').split(',').map(Number);
    if (cam.length === 6 && cam.every(Number.isFinite)) {
      camera.position.set(cam[0], cam[1], cam[2]);
      controls.target.set(cam[3], cam[4], cam[5]);
    } else {
      const d = 1.05 * R / Math.tan(camera.fov * Math.PI / 360);
      controls.target.copy(C);
      camera.position.set(C.x + 0.55 * d, C.y - 0.78 * d, C.z + 0.3 * d);
    }
    controls.update();
  }
  home();
  if (!flat) {
    scene.add(new THREE.HemisphereLight(0xffffff, 0x606060, 0.75));
    const sun = new THREE.DirectionalLight(0xffffff, 0.55);
    sun.position.set(2, -3, 5);
    scene.add(sun);
    const step = Math.pow(10, Math.floor(Math.log10(R))) / 2;
    const grid = new THREE.GridHelper(40 * step, 40, 0x9098a0, 0xc8ccd0);
    grid.rotation.x = Math.PI / 2;
    grid.position.set(Math.round(C.x / step) * step, Math.round(C.y / step) * step, 0);
    const floor = new THREE.Group(); // the grid at z = floor, or on the contact's ground
    floor.position.z = data.floor;
    floor.add(grid);
    const plane = data.obstacles.find(function (w) { return w.k === 'plane'; });
    if (plane) {
      const n = new THREE.Vector3().fromArray(plane.n);
      floor.quaternion.setFromUnitVectors(new THREE.Vector3(0, 0, 1), n);
      floor.position.copy(n.multiplyScalar(plane.d));
      const ground = new THREE.Mesh(new THREE.PlaneBufferGeometry(40 * step, 40 * step),
          material([0.75, 0.8, 0.72, 0.45], 1));
      ground.position.copy(grid.position);
      floor.add(ground);
    }
    scene.add(floor);
    scene.add(new THREE.AxesHelper(Math.min(0.3, R / 3)));
  }

  // The meshes, parsed once.
  const parsed = data.meshes.map(function (m) {
    try {
      if (m.f === 'stl') return {geometry: new THREE.STLLoader().parse(bytes(m.d).buffer)};
      const text = new TextDecoder().decode(bytes(m.d));
      if (m.f === 'obj') return {object: new THREE.OBJLoader().parse(text)};
      const dae = new THREE.ColladaLoader().parse(text, '');
      dae.scene.rotation.set(0, 0, 0); // URDF meshes are in the link's frame as they are
      dae.scene.updateMatrix();
      return {object: dae.scene};
    } catch (e) {
      return {error: String(e)};
    }
  });
  function material(c, opacity) {
    const o = {color: new THREE.Color(c[0], c[1], c[2]), side: THREE.DoubleSide};
    const a = (c[3] < 0 ? 1 : c[3]) * opacity;
    if (a < 1) { o.transparent = true; o.opacity = a; o.depthWrite = opacity === 1; }
    return flat ? new THREE.MeshBasicMaterial(o) : new THREE.MeshPhongMaterial(o);
  }
  function shape(s, opacity) {
    const m = material(s.c, opacity);
    const z = function (g) { g.rotateX(Math.PI / 2); return g; }; // three's y axis → URDF's z
    if (s.k === 'box') return new THREE.Mesh(new THREE.BoxBufferGeometry(s.s[0], s.s[1], s.s[2]), m);
    if (s.k === 'sphere') return new THREE.Mesh(new THREE.SphereBufferGeometry(s.s[0], 24, 16), m);
    if (s.k === 'cylinder')
      return new THREE.Mesh(z(new THREE.CylinderBufferGeometry(s.s[0], s.s[0], s.s[1], 32)), m);
    if (s.k === 'capsule') {
      const g = new THREE.Group();
      g.add(new THREE.Mesh(z(new THREE.CylinderBufferGeometry(s.s[0], s.s[0], s.s[1], 24)), m));
      for (const e of [-0.5, 0.5]) {
        const b = new THREE.Mesh(new THREE.SphereBufferGeometry(s.s[0], 24, 12), m);
        b.position.z = e * s.s[1];
        g.add(b);
      }
      return g;
    }
    const mesh = parsed[s.m];
    let o;
    if (mesh.geometry) {
      o = new THREE.Mesh(mesh.geometry, material(s.c[3] < 0 ? [0.7, 0.7, 0.7, 1] : s.c, opacity));
    } else if (mesh.object) {
      o = mesh.object.clone();
      o.traverse(function (n) {
        if (!n.isMesh) return;
        if (s.c[3] >= 0 || flat || opacity < 1) {
          const old = Array.isArray(n.material) ? n.material[0] : n.material;
          const c = s.c[3] >= 0 ? s.c : old && old.color ? [old.color.r, old.color.g, old.color.b, 1] : [0.7, 0.7, 0.7, 1];
          n.material = material(c, opacity);
        }
      });
    } else {
      o = new THREE.Group();
    }
    const g = new THREE.Group();
    o.scale.multiply(new THREE.Vector3(s.s[0], s.s[1], s.s[2])); // after COLLADA's <unit>
    g.add(o);
    return g;
  }
  // A robot: one group per drawn body (index 0: the ground), posed by pose().
  function robot(opacity) {
    const groups = [];
    for (let b = 0; b <= nb; b++) {
      const g = new THREE.Group();
      scene.add(g);
      groups.push(g);
    }
    for (const s of data.shapes) {
      const o = shape(s, opacity);
      o.position.fromArray(s.p);
      o.quaternion.fromArray(s.r);
      groups[s.b].add(o);
    }
    return groups;
  }
  const qa = new THREE.Quaternion(), qb = new THREE.Quaternion();
  const va = new THREE.Vector3(), vb = new THREE.Vector3();
  function frameAt(time) { // k with T[k] <= time < T[k+1], and the fraction between them
    if (!(time > T[0])) return [0, 0];
    if (time >= T[nf - 1]) return [nf - 1, 0];
    let lo = 0, hi = nf - 1;
    while (hi - lo > 1) {
      const mid = (lo + hi) >> 1;
      if (T[mid] <= time) lo = mid; else hi = mid;
    }
    return [lo, (time - T[lo]) / (T[hi] - T[lo])];
  }
  function pose(groups, time) {
    const [k, a] = frameAt(time);
    const k2 = Math.min(k + 1, nf - 1);
    for (let b = 0; b < nb; b++) {
      const i = 7 * (k * nb + b), j = 7 * (k2 * nb + b);
      va.set(P[i], P[i + 1], P[i + 2]);
      vb.set(P[j], P[j + 1], P[j + 2]);
      qa.set(P[i + 3], P[i + 4], P[i + 5], P[i + 6]);
      qb.set(P[j + 3], P[j + 4], P[j + 5], P[j + 6]);
      groups[b + 1].position.copy(va.lerp(vb, a));
      groups[b + 1].quaternion.copy(qa.slerp(qb, a));
    }
    return [k, k2, a];
  }

  const main = robot(1);
  // The static boxes the robot touches, and its contact points at each frame (red).
  for (const w of data.obstacles) {
    if (w.k !== 'box') continue;
    const box = new THREE.Mesh(new THREE.BoxBufferGeometry(w.s[0], w.s[1], w.s[2]),
        material([0.6, 0.55, 0.5, 0.7], 1));
    box.position.fromArray(w.c);
    scene.add(box);
  }
  const TC = new Uint32Array(bytes(data.touches).buffer);
  const TP = new Float32Array(bytes(data.touch).buffer);
  const first = new Uint32Array(TC.length + 1);
  for (let k = 0; k < TC.length; k++) first[k + 1] = first[k] + TC[k];
  const dots = [], dot = new THREE.SphereBufferGeometry(Math.max(0.006, R / 90), 12, 8);
  const red = new THREE.MeshBasicMaterial({color: 0xd62728});
  function touching(k) {
    const n = k < TC.length ? TC[k] : 0;
    while (dots.length < n) { const d = new THREE.Mesh(dot, red); scene.add(d); dots.push(d); }
    for (let i = 0; i < dots.length; i++) {
      dots[i].visible = i < n;
      if (i < n) dots[i].position.fromArray(TP, 3 * (first[k] + i));
    }
  }
  // The contact forces of each frame (run --animate): arrows from their points, of length the
  // force times data.arrowScale [m/N].
  const AC = new Uint32Array(bytes(data.arrowCounts).buffer);
  const AF = new Float32Array(bytes(data.arrows).buffer);
  const afirst = new Uint32Array(AC.length + 1);
  for (let k = 0; k < AC.length; k++) afirst[k + 1] = afirst[k] + AC[k];
  const arrows = [];
  function pushing(k) {
    const n = k < AC.length ? AC[k] : 0;
    while (arrows.length < n) {
      const a = new THREE.ArrowHelper(new THREE.Vector3(0, 0, 1), new THREE.Vector3(), 1, 0x1f5fd0);
      scene.add(a);
      arrows.push(a);
    }
    for (let i = 0; i < arrows.length; i++) {
      const o = 6 * (afirst[k] + i);
      const f = i < n ? new THREE.Vector3(AF[o + 3], AF[o + 4], AF[o + 5]) : null;
      const len = f ? f.length() * data.arrowScale : 0;
      arrows[i].visible = len > 0;
      if (!(len > 0)) continue;
      arrows[i].position.set(AF[o], AF[o + 1], AF[o + 2]);
      arrows[i].setDirection(f.normalize());
      arrows[i].setLength(len, Math.min(0.25 * len, R / 12), Math.min(0.12 * len, R / 25));
    }
  }
  for (const g of (hash.get('ghosts') || '').split(',').filter(function (x) { return x !== ''; })) {
    const t = Number(g);
    if (Number.isFinite(t)) pose(robot(0.35), t);
  }

  // The panel: the time and the coordinates.
  const timeText = document.getElementById('time');
  const table = document.getElementById('joints');
  const cells = data.names.map(function (name) {
    const row = table.insertRow();
    row.insertCell().textContent = name;
    const v = row.insertCell();
    v.className = 'v';
    return v;
  });
  const slider = document.getElementById('slider');
  const t0 = T[0], t1 = T[nf - 1];
  let time = t0, playing = true, last = null;
  const start = Number(hash.get('t'));
  if (hash.has('t') && Number.isFinite(start)) { time = Math.min(Math.max(start, t0), t1); playing = false; }
  if (hash.get('play') === '0') playing = false;
  const speed = document.getElementById('speed');
  if (hash.has('speed')) {
    const o = document.createElement('option');
    o.textContent = hash.get('speed');
    speed.appendChild(o);
    speed.value = o.textContent;
  }
  const playButton = document.getElementById('play');
  function show() {
    const [k, k2, a] = pose(main, time);
    touching(a < 0.5 ? k : k2);
    pushing(a < 0.5 ? k : k2);
    timeText.textContent = 't = ' + time.toFixed(3) + ' s of ' + t1.toFixed(3) + ' s';
    for (let i = 0; i < nq; i++)
      cells[i].textContent = (Q[k * nq + i] + a * (Q[k2 * nq + i] - Q[k * nq + i])).toFixed(4);
    if (document.activeElement !== slider)
      slider.value = t1 > t0 ? Math.round(1000 * (time - t0) / (t1 - t0)) : 0;
    playButton.textContent = playing ? 'pause' : 'play';
    renderer.render(scene, camera);
  }
  function tick(now) {
    if (playing && last !== null) {
      time += (now - last) / 1000 * Number(speed.value);
      if (time > t1) {
        if (document.getElementById('loop').checked) time = t0; else { time = t1; playing = false; }
      }
    }
    last = now;
    show();
    requestAnimationFrame(tick);
  }
  playButton.onclick = function () { playing = !playing; last = null; if (time >= t1) time = t0; };
  slider.oninput = function () { time = t0 + (t1 - t0) * slider.value / 1000; };
  document.getElementById('home').onclick = home;
  window.addEventListener('keydown', function (e) {
    if (e.key === ' ') { playButton.onclick(); e.preventDefault(); }
    if (e.key === 'h') home();
  });
  window.addEventListener('resize', function () {
    camera.aspect = window.innerWidth / window.innerHeight;
    camera.updateProjectionMatrix();
    renderer.setSize(window.innerWidth, window.innerHeight);
  });
  show();
  document.body.dataset.ready = '1';
  requestAnimationFrame(tick);
})();
)js";
}

} // namespace varsym::models::animation_detail

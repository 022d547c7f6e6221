// lcpsim trajectory viewer: draws one run from the data inlined in the page
// (element #lcpsim-data, written by lcpsim.viewer). Classic script: the page's
// boot code loads three.js and OrbitControls as modules from inlined text and
// calls lcpsimStartViewer(THREE, OrbitControls, data).
// Simulation frame: z up, quaternions (w, x, y, z), impulses in N·s.
"use strict";

function lcpsimDecode(a) {
  const bin = atob(a.b64);
  const bytes = new Uint8Array(bin.length);
  for (let i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
  const T = { f4: Float32Array, f8: Float64Array, i4: Int32Array, u1: Uint8Array }[a.dtype];
  return new T(bytes.buffer);
}

function lcpsimFmt(x, digits) {
  if (x === null || x === undefined || Number.isNaN(x)) return "—";
  if (x === 0) return "0";
  const ax = Math.abs(x);
  return ax >= 1e-3 && ax < 1e5 ? x.toPrecision(digits || 4) : x.toExponential((digits || 4) - 1);
}

function lcpsimStartViewer(THREE, OrbitControls, D) {
  const $ = (id) => document.getElementById(id);
  const A = {};
  for (const [k, v] of Object.entries(D.arrays)) A[k] = lcpsimDecode(v);
  const F = D.frames, ND = D.dynamic.length;
  const statusColor = (name) => D.status_colors[name] || D.status_colors.failed;

  // ---------------------------------------------------------------- scene
  const view = $("view");
  let renderer = null;
  try {
    renderer = new THREE.WebGLRenderer({ canvas: $("scene"), antialias: true, preserveDrawingBuffer: true });
  } catch (e) {
    $("webgl-error").hidden = false;
    $("webgl-error").textContent = "WebGL is not available in this browser, so the 3-D view is off: " + e.message;
  }
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0xf4f5f7);
  const camera = new THREE.PerspectiveCamera(40, 1, 0.01, 1000);
  camera.up.set(0, 0, 1);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x8899aa, 1.6));
  const sun = new THREE.DirectionalLight(0xffffff, 1.6);
  sun.position.set(-3, -5, 8);
  scene.add(sun);

  const v3 = (a, i) => new THREE.Vector3(a[i], a[i + 1], a[i + 2]);
  const center = new THREE.Vector3(...D.view.center);
  // A box, sphere, capsule, cylinder, hull, mesh or height field of `color` at the origin (null for other kinds).
  function solidObject(b, color) {
    let obj = null;
    if (b.kind === "box") {
      const he = b.half_extents;
      const geo = new THREE.BoxGeometry(2 * he[0], 2 * he[1], 2 * he[2]);
      obj = new THREE.Mesh(geo, new THREE.MeshStandardMaterial({ color: color, roughness: 0.7 }));
      obj.add(new THREE.LineSegments(new THREE.EdgesGeometry(geo), new THREE.LineBasicMaterial({ color: 0x222222 })));
    } else if (b.kind === "sphere") {
      const geo = new THREE.SphereGeometry(b.radius, 32, 16);
      const col = new THREE.Color(color), dark = col.clone().multiplyScalar(0.45);
      const pos = geo.attributes.position, colors = [];
      for (let k = 0; k < pos.count; k++) {  // octants in two shades: the rotation shows
        const c = pos.getX(k) * pos.getY(k) * pos.getZ(k) >= 0 ? col : dark;
        colors.push(c.r, c.g, c.b);
      }
      geo.setAttribute("color", new THREE.Float32BufferAttribute(colors, 3));
      obj = new THREE.Mesh(geo, new THREE.MeshStandardMaterial({ vertexColors: true, roughness: 0.6 }));
    } else if (b.kind === "capsule" || b.kind === "cylinder") {
      const geo = b.kind === "capsule"
        ? new THREE.CapsuleGeometry(b.radius, 2 * b.half_length, 8, 24)
        : new THREE.CylinderGeometry(b.radius, b.radius, 2 * b.half_length, 32);
      geo.rotateX(Math.PI / 2);  // three's axis y onto the body's z (lcpsim's, as in MJCF)
      obj = new THREE.Mesh(geo, new THREE.MeshStandardMaterial({ color: color, roughness: 0.6 }));
      obj.add(new THREE.LineSegments(new THREE.EdgesGeometry(geo, 40), new THREE.LineBasicMaterial({ color: 0x222222 })));
    } else if ((b.kind === "convex" || b.kind === "mesh") && b.vertices && b.faces) {
      const geo = new THREE.BufferGeometry();
      geo.setAttribute("position", new THREE.Float32BufferAttribute(b.vertices.flat(), 3));
      geo.setIndex(b.faces.flat());
      geo.computeVertexNormals();
      const mat = new THREE.MeshStandardMaterial({
        color: color, roughness: 0.7, flatShading: true, side: THREE.DoubleSide,
        transparent: b.kind === "mesh", opacity: b.kind === "mesh" ? 0.6 : 1,
      });
      obj = new THREE.Mesh(geo, mat);
      obj.add(new THREE.LineSegments(new THREE.EdgesGeometry(geo, 20), new THREE.LineBasicMaterial({ color: 0x222222 })));
    } else if (b.kind === "hfield" && b.heights) {
      // The grid of heights: row r at y = −hy + 2hy·r/(nrow − 1), column c at x likewise.
      const nr = b.heights.length, nc = b.heights[0].length, [hx, hy] = b.half_extents;
      const pos = [], idx = [];
      for (let r = 0; r < nr; r++) {
        for (let c = 0; c < nc; c++) pos.push(-hx + 2 * hx * c / (nc - 1), -hy + 2 * hy * r / (nr - 1), b.heights[r][c]);
      }
      for (let r = 0; r + 1 < nr; r++) {
        for (let c = 0; c + 1 < nc; c++) {
          const k = r * nc + c;
          idx.push(k, k + 1, k + nc + 1, k, k + nc + 1, k + nc);
        }
      }
      const geo = new THREE.BufferGeometry();
      geo.setAttribute("position", new THREE.Float32BufferAttribute(pos, 3));
      geo.setIndex(idx);
      geo.computeVertexNormals();
      obj = new THREE.Mesh(geo, new THREE.MeshStandardMaterial({ color: color, roughness: 0.9, side: THREE.DoubleSide }));
    }
    return obj;
  }

  const meshes = new Map();  // body index -> Object3D
  D.bodies.forEach((b, i) => {
    let obj = null;
    if (b.kind === "plane") {
      obj = planeObject(b);
    } else if (b.kind === "compound" && b.parts) {
      obj = new THREE.Group();  // each part at its pose in the body frame
      for (const p of b.parts) {
        const part = solidObject(p, bodyColor(i, b));
        if (!part) continue;
        part.position.set(...p.position);
        part.quaternion.set(p.orientation[1], p.orientation[2], p.orientation[3], p.orientation[0]);
        obj.add(part);
      }
    } else if ((obj = solidObject(b, bodyColor(i, b)))) {
      // a single solid
    } else {
      obj = new THREE.Mesh(new THREE.SphereGeometry(0.05 * D.view.size), new THREE.MeshBasicMaterial({ color: 0x888888 }));
    }
    if (b.kind !== "plane") {
      obj.position.set(...b.position);
      obj.quaternion.set(b.orientation[1], b.orientation[2], b.orientation[3], b.orientation[0]);
    }
    scene.add(obj);
    meshes.set(i, obj);
  });

  function bodyColor(i, b) {
    if (b.static) return 0x9aa3ad;
    if (i === D.focus) return 0xe8702a;
    const palette = [0x3f7fbf, 0x5aa05a, 0xb0527c, 0x8c6bb1, 0xc9a227, 0x4aa5a5];
    return palette[i % palette.length];
  }

  function planeObject(b) {
    const n = new THREE.Vector3(...b.normal).normalize();
    const size = D.view.plane_size;
    const g = new THREE.Group();
    const c = center.clone().addScaledVector(n, b.offset - center.dot(n));
    g.position.copy(c);
    const plane = new THREE.Mesh(new THREE.PlaneGeometry(size, size),
      new THREE.MeshStandardMaterial({ color: 0xc9ced6, roughness: 1, side: THREE.DoubleSide }));
    plane.quaternion.setFromUnitVectors(new THREE.Vector3(0, 0, 1), n);
    const divisions = Math.max(2, Math.round(size / D.view.grid));
    const grid = new THREE.GridHelper(size, divisions, 0x59606b, 0x868e99);
    grid.rotation.x = Math.PI / 2;  // the grid's normal (y) onto the plane's (local z), then on the plane
    grid.position.z = 1e-3 * D.view.size;
    plane.add(grid);
    g.add(plane);
    return g;
  }

  // Contacts: points (instanced spheres), normal and friction impulses (line shafts + cone heads).
  const maxC = Math.max(1, D.max_contacts);
  const pointGeo = new THREE.SphereGeometry(0.025 * D.view.size, 10, 6);
  // Contacts are drawn over the bodies (no depth test): they sit on faces and point into bodies.
  const overlay = (color) => ({ color, depthTest: false, transparent: true });
  const points = new THREE.InstancedMesh(pointGeo, new THREE.MeshBasicMaterial(overlay(0x111111)), maxC);
  points.frustumCulled = false;
  points.renderOrder = 2;
  scene.add(points);
  const arrows = { normal: makeArrows(0x1f5fd6), friction: makeArrows(0xd62f2f) };

  function makeArrows(color) {
    const geo = new THREE.BufferGeometry();
    geo.setAttribute("position", new THREE.BufferAttribute(new Float32Array(maxC * 6), 3));
    const lines = new THREE.LineSegments(geo, new THREE.LineBasicMaterial(overlay(color)));
    lines.frustumCulled = false;
    lines.renderOrder = 3;
    const head = new THREE.ConeGeometry(0.03 * D.view.size, 0.09 * D.view.size, 10);
    head.translate(0, -0.045 * D.view.size, 0);  // tip at the origin
    const heads = new THREE.InstancedMesh(head, new THREE.MeshBasicMaterial(overlay(color)), maxC);
    heads.frustumCulled = false;
    heads.renderOrder = 3;
    scene.add(lines, heads);
    return { lines, heads };
  }

  // Joints at their anchors along their axes, over the bodies as the contacts are:
  // a hinge's axle, a slider's rail, a ball joint's ball, a weld's cube.
  const NJ = D.joints.length, js = D.view.size;
  const jointMaterial = new THREE.MeshBasicMaterial(overlay(0x8e3fb5));
  const jointGeometry = {
    hinge: () => new THREE.CylinderGeometry(0.08 * js, 0.08 * js, 0.8 * js, 16),
    slider: () => new THREE.CylinderGeometry(0.02 * js, 0.02 * js, 1.6 * js, 8),
    ball: () => new THREE.SphereGeometry(0.12 * js, 16, 8),
    fixed: () => new THREE.BoxGeometry(0.16 * js, 0.16 * js, 0.16 * js),
  };
  const joints = D.joints.map((j) => {
    const m = new THREE.Mesh((jointGeometry[j.kind] || jointGeometry.ball)(), jointMaterial);
    m.renderOrder = 4;
    m.frustumCulled = false;
    scene.add(m);
    return m;
  });
  const jointAxis = new THREE.Vector3(), yAxis = new THREE.Vector3(0, 1, 0);  // three's cylinder axis: y
  function drawJoints() {
    const on = $("show-joints").checked;
    for (let j = 0; j < NJ; j++) {
      const m = joints[j], o = 3 * (frame * NJ + j);
      m.visible = on;
      m.position.set(A.j_anchor[o], A.j_anchor[o + 1], A.j_anchor[o + 2]);
      jointAxis.set(A.j_axis[o], A.j_axis[o + 1], A.j_axis[o + 2]).normalize();
      m.quaternion.setFromUnitVectors(yAxis, jointAxis);
    }
  }
  $("joints-toggle").hidden = NJ === 0;

  // ---------------------------------------------------------------- camera
  const controls = new OrbitControls(camera, renderer ? renderer.domElement : $("scene"));
  const target = new THREE.Vector3(...D.view.target);
  camera.position.copy(target).add(new THREE.Vector3(...D.view.eye_offset));
  controls.target.copy(target);
  controls.update();
  controls.addEventListener("change", () => render());

  function resize() {
    const w = view.clientWidth, h = view.clientHeight;
    if (renderer) renderer.setSize(w, h, false);
    camera.aspect = w / Math.max(1, h);
    camera.updateProjectionMatrix();
    drawStrip();
    render();
  }
  window.addEventListener("resize", resize);

  // ---------------------------------------------------------------- frames
  let frame = 0;
  const M = new THREE.Matrix4(), Q = new THREE.Quaternion(), S = new THREE.Vector3(1, 1, 1), up = new THREE.Vector3(0, 1, 0);

  function setFrame(f) {
    frame = Math.max(0, Math.min(F - 1, f | 0));
    for (let j = 0; j < ND; j++) {
      const o = (frame * ND + j) * 7, p = A.pose;
      const m = meshes.get(D.dynamic[j]);
      m.position.set(p[o], p[o + 1], p[o + 2]);
      m.quaternion.set(p[o + 4], p[o + 5], p[o + 6], p[o + 3]);
    }
    drawContacts();
    drawJoints();
    $("slider").value = String(frame);
    readout();
    render();
  }

  function drawContacts() {
    const a = A.c_offsets ? A.c_offsets[frame] : 0, b = A.c_offsets ? A.c_offsets[frame + 1] : 0;
    const n = b - a, k = D.impulse.length_per_Ns;
    points.count = $("show-points").checked ? n : 0;
    for (let c = 0; c < n; c++) {
      M.makeTranslation(A.c_point[3 * (a + c)], A.c_point[3 * (a + c) + 1], A.c_point[3 * (a + c) + 2]);
      points.setMatrixAt(c, M);
    }
    points.instanceMatrix.needsUpdate = true;
    setArrows(arrows.normal, $("show-normal").checked, a, n, (c, out) => {
      const fn = A.c_fn[a + c] * k;
      out.set(A.c_normal[3 * (a + c)] * fn, A.c_normal[3 * (a + c) + 1] * fn, A.c_normal[3 * (a + c) + 2] * fn);
    });
    setArrows(arrows.friction, $("show-friction").checked, a, n, (c, out) => {
      out.set(A.c_friction[3 * (a + c)] * k, A.c_friction[3 * (a + c) + 1] * k, A.c_friction[3 * (a + c) + 2] * k);
    });
  }

  const tail = new THREE.Vector3(), tip = new THREE.Vector3(), vec = new THREE.Vector3();
  function setArrows(set, on, a, n, vector) {
    const pos = set.lines.geometry.attributes.position;
    let m = 0;
    for (let c = 0; on && c < n; c++) {
      vector(c, vec);
      const len = vec.length();
      if (len < 1e-6 * D.view.size) continue;  // nothing to draw
      if (len > 3 * D.view.size) vec.multiplyScalar((3 * D.view.size) / len);  // a failed solve's wild iterate
      tail.set(A.c_point[3 * (a + c)], A.c_point[3 * (a + c) + 1], A.c_point[3 * (a + c) + 2]);
      tip.copy(tail).add(vec);
      pos.setXYZ(2 * m, tail.x, tail.y, tail.z);
      pos.setXYZ(2 * m + 1, tip.x, tip.y, tip.z);
      Q.setFromUnitVectors(up, vec.normalize());
      M.compose(tip, Q, S);
      set.heads.setMatrixAt(m, M);
      m++;
    }
    set.lines.geometry.setDrawRange(0, 2 * m);
    pos.needsUpdate = true;
    set.heads.count = m;
    set.heads.instanceMatrix.needsUpdate = true;
  }

  function render() {
    if (renderer) renderer.render(scene, camera);
  }

  // ---------------------------------------------------------------- readouts
  const stepOf = (f) => A.frame_step[f];
  function readout() {
    const st = stepOf(frame);
    const status = st > 0 ? D.status_names[A.step_status[st - 1]] : "initial state";
    const el = $("step-readout");
    el.textContent = (st > 0 ? `step ${st} / ${D.steps}` : `initial state (${D.steps} steps)`) +
      ` · t = ${A.frame_time[frame].toFixed(4)} s · frame ${frame + 1} / ${F}`;
    const s = $("lcp-readout");
    s.textContent = st > 0
      ? `LCP: ${status}${status === "no_contact" ? "" : ` · pivots ${A.frame_pivots[frame]} · residual ${lcpsimFmt(A.frame_residual[frame], 3)}`}`
      : "LCP: —";
    s.style.color = st > 0 && D.failed_statuses.includes(status) ? "#c0191f" : "";
    const a = A.c_offsets ? A.c_offsets[frame] : 0, b = A.c_offsets ? A.c_offsets[frame + 1] : 0;
    let fn = 0, lam = 0;
    for (let c = a; c < b; c++) { fn += A.c_fn[c]; lam = Math.max(lam, A.c_lam[c]); }
    const failed = st > 0 && D.failed_statuses.includes(status);
    $("contact-readout").textContent = !D.has_contacts ? "contacts: not recorded in this trajectory"
      : `contacts: ${b - a} · Σ fn = ${lcpsimFmt(fn, 4)} N·s · max λ = ${lcpsimFmt(lam, 3)} m/s` +
        (failed ? " — the solver's last iterate (arrows capped at 3 body sizes); no impulse was applied" : "");
    bodyReadout();
  }

  function bodyReadout() {
    const bi = Number($("body-select").value);
    const j = D.dynamic.indexOf(bi);
    if (j < 0) { $("body-readout").textContent = "—"; return; }
    let pos, disp, tilt, along;
    if (bi === D.focus) {  // double precision, computed by lcpsim
      pos = [0, 1, 2].map((k) => A.focus_position[3 * frame + k]);
      disp = [0, 1, 2].map((k) => A.focus_displacement[3 * frame + k]);
      tilt = A.focus_tilt_deg[frame];
      along = D.direction ? A.focus_along[frame] : null;
    } else {  // from the single-precision poses
      const o = (frame * ND + j) * 7, o0 = j * 7, p = A.pose;
      pos = [p[o], p[o + 1], p[o + 2]];
      disp = [0, 1, 2].map((k) => p[o + k] - p[o0 + k]);
      const q = new THREE.Quaternion(p[o + 4], p[o + 5], p[o + 6], p[o + 3]);
      const q0 = new THREE.Quaternion(p[o0 + 4], p[o0 + 5], p[o0 + 6], p[o0 + 3]);
      tilt = THREE.MathUtils.radToDeg(q0.angleTo(q));
      along = D.direction ? disp[0] * D.direction[0] + disp[1] * D.direction[1] + disp[2] * D.direction[2] : null;
    }
    const o = (frame * ND + j) * 7, p = A.pose;
    const quat = [p[o + 3], p[o + 4], p[o + 5], p[o + 6]];
    const lines = [
      `body ${bi} (${D.bodies[bi].kind})${bi === D.focus ? "" : " · single precision"}`,
      `position (${pos.map((x) => lcpsimFmt(x, 6)).join(", ")}) m`,
      `orientation (w, x, y, z) (${quat.map((x) => x.toFixed(5)).join(", ")})`,
      `tilt from start: ${lcpsimFmt(tilt, 4)}°`,
      `displacement (${disp.map((x) => lcpsimFmt(x, 4)).join(", ")}) m`,
    ];
    if (along !== null) lines.push(`${D.direction_label}: ${lcpsimFmt(along, 6)} m`);
    $("body-readout").textContent = lines.join("\n");
  }

  // ---------------------------------------------------------------- status strip
  const strip = $("strip");
  function drawStrip() {
    const w = strip.clientWidth, h = strip.clientHeight;
    strip.width = w; strip.height = h;
    const g = strip.getContext("2d");
    g.fillStyle = "#e6e8eb";
    g.fillRect(0, 0, w, h);
    const T = D.steps;
    if (T === 0) return;
    // Each pixel column shows its steps' worst status: a failed step is never hidden.
    const rank = D.status_names.map((s) => (D.failed_statuses.includes(s) ? 3 : s === "no_contact" ? 1 : 2));
    for (let x = 0; x < w; x++) {
      const a = Math.floor((x * T) / w), b = Math.max(a + 1, Math.floor(((x + 1) * T) / w));
      let worst = -1, name = null;
      for (let i = a; i < b && i < T; i++) {
        const code = A.step_status[i];
        if (rank[code] > worst) { worst = rank[code]; name = D.status_names[code]; }
      }
      g.fillStyle = statusColor(name);
      g.fillRect(x, worst === 3 ? 0 : h * 0.3, 1, worst === 3 ? h : h * 0.7);
    }
    placeMarkers();
  }

  function placeMarkers() {
    const box = $("markers");
    box.textContent = "";
    const w = strip.clientWidth;
    for (const [first, last] of D.failed_runs) {
      const m = document.createElement("button");
      m.className = "fail-marker";
      m.dataset.step = String(first);
      m.title = last > first ? `LCP failed at steps ${first}–${last}` : `LCP failed at step ${first}`;
      m.style.left = `${((first - 0.5) / D.steps) * w}px`;
      m.addEventListener("click", () => jumpToStep(first));
      box.appendChild(m);
    }
  }

  function jumpToStep(step) {
    let lo = 0, hi = F - 1;  // first frame whose step is >= step
    while (lo < hi) {
      const mid = (lo + hi) >> 1;
      if (stepOf(mid) < step) lo = mid + 1; else hi = mid;
    }
    pause();
    setFrame(lo);
  }
  strip.addEventListener("click", (e) => {
    const r = strip.getBoundingClientRect();
    jumpToStep(Math.floor(((e.clientX - r.left) / r.width) * D.steps) + 1);
  });

  // ---------------------------------------------------------------- playback
  let playing = false, simTime = 0, last = 0;
  function play() {
    if (F < 2) return;
    if (frame >= F - 1) setFrame(0);
    playing = true; simTime = A.frame_time[frame]; last = performance.now();
    $("play").textContent = "❚❚ pause";
    requestAnimationFrame(tick);
  }
  function pause() { playing = false; $("play").textContent = "▶ play"; }
  function tick(now) {
    if (!playing) return;
    simTime += ((now - last) / 1000) * Number($("speed").value);
    last = now;
    let f = frame;
    while (f < F - 1 && A.frame_time[f + 1] <= simTime) f++;
    if (f !== frame) setFrame(f);
    if (frame >= F - 1) { pause(); return; }
    requestAnimationFrame(tick);
  }
  $("play").addEventListener("click", () => (playing ? pause() : play()));
  $("slider").max = String(F - 1);
  $("slider").addEventListener("input", () => { pause(); setFrame(Number($("slider").value)); });
  for (const id of ["show-points", "show-normal", "show-friction", "show-joints"]) $(id).addEventListener("change", () => setFrame(frame));
  $("body-select").addEventListener("change", () => bodyReadout());
  window.addEventListener("keydown", (e) => {
    if (e.target.tagName === "SELECT") return;
    if (e.key === " ") { e.preventDefault(); playing ? pause() : play(); }
    if (e.key === "ArrowRight") { pause(); setFrame(frame + 1); }
    if (e.key === "ArrowLeft") { pause(); setFrame(frame - 1); }
  });

  for (const bi of D.dynamic) {
    const o = document.createElement("option");
    o.value = String(bi);
    o.textContent = `body ${bi} (${D.bodies[bi].kind})${bi === D.focus ? " ★" : ""}`;
    $("body-select").appendChild(o);
  }
  $("body-select").value = String(D.focus);
  $("legend-scale").textContent = D.impulse.legend;

  resize();
  setFrame(0);
  // For tests and scripting: the viewer's state and controls.
  window.lcpsimViewer = {
    frames: F, steps: D.steps, setFrame, jumpToStep, play, pause,
    get frame() { return frame; }, get step() { return stepOf(frame); }, get playing() { return playing; },
    webgl: renderer !== null,
    joints: NJ,
    // Where joint j is drawn now: its position and its axis (the drawn object's y).
    jointPose: (j) => [joints[j].position.toArray(), yAxis.clone().applyQuaternion(joints[j].quaternion).toArray()],
    // The world box [min, max] of what is drawn for body i now, and showing or hiding it.
    bodyBounds: (i) => {
      const b = new THREE.Box3().setFromObject(meshes.get(i));
      return [b.min.toArray(), b.max.toArray()];
    },
    showBody: (i, on) => { meshes.get(i).visible = on; render(); },
  };
  document.body.dataset.ready = "1";
}

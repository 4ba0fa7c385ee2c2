// lieflow's replay page: draws the bodies of one run at the poses its CSV
// holds, frame by frame (no interpolation: what is drawn at a time is the
// last row at or before it, exactly as written). The data block
// (#lieflow-run, written by replay/replay_page.cpp) holds the kept columns
// as little-endian float64 in base64, the bodies' shapes and the joints'
// markers. Test hooks: `#t=SECONDS` opens paused at that time, and
// #lieflow-state holds the drawn poses (from the scene graph's world
// matrices) whenever the player is paused.
(function () {
  'use strict';
  const D = JSON.parse(document.getElementById('lieflow-run').textContent);

  function bytes(b64) {
    const s = atob(b64);
    const u = new Uint8Array(s.length);
    for (let i = 0; i < s.length; ++i) u[i] = s.charCodeAt(i);
    return u;
  }
  const values = new Float64Array(bytes(D.values).buffer);
  const C = D.columns.length, N = D.frames;
  const at = (frame, column) => values[frame * C + column];
  const times = new Float64Array(N);
  for (let i = 0; i < N; ++i) times[i] = at(i, 0);

  // ---- scene graph -------------------------------------------------------
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0xf2f2f0);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x8a8a80, 0.75));
  const sun = new THREE.DirectionalLight(0xffffff, 0.65);
  sun.position.set(2, -3, 5);
  scene.add(sun);
  const extent = D.extent;

  const color = (rgba) => new THREE.Color(rgba[0], rgba[1], rgba[2]);
  function material(rgba) {
    return new THREE.MeshStandardMaterial({
      color: color(rgba), opacity: rgba[3], transparent: rgba[3] < 1, metalness: 0.05, roughness: 0.75,
      side: THREE.DoubleSide,
    });
  }
  const Z_FROM_Y = new THREE.Matrix4().makeRotationX(Math.PI / 2);  // three's cylinders lie along y

  function meshOf(shape) {
    const m = material(shape.rgba);
    const s = shape.size;
    switch (shape.kind) {
      case 'box': return new THREE.Mesh(new THREE.BoxBufferGeometry(2 * s[0], 2 * s[1], 2 * s[2]), m);
      case 'sphere': return new THREE.Mesh(new THREE.SphereBufferGeometry(s[0], 24, 16), m);
      case 'ellipsoid': {
        const g = new THREE.SphereBufferGeometry(1, 24, 16);
        g.scale(s[0], s[1], s[2]);
        return new THREE.Mesh(g, m);
      }
      case 'cylinder': {
        const g = new THREE.CylinderBufferGeometry(s[0], s[0], 2 * s[1], 24);
        g.applyMatrix(Z_FROM_Y);
        return new THREE.Mesh(g, m);
      }
      case 'capsule': {
        const group = new THREE.Group();
        const g = new THREE.CylinderBufferGeometry(s[0], s[0], 2 * s[1], 24, 1, true);
        g.applyMatrix(Z_FROM_Y);
        group.add(new THREE.Mesh(g, m));
        for (const z of [-s[1], s[1]]) {
          const cap = new THREE.Mesh(new THREE.SphereBufferGeometry(s[0], 24, 12), m);
          cap.position.set(0, 0, z);
          group.add(cap);
        }
        return group;
      }
      case 'mesh': return meshFile(shape, m);
    }
    throw new Error('lieflow replay: unknown shape kind ' + shape.kind);
  }

  function meshFile(shape, m) {
    let object;
    if (shape.format === 'triangles') {
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(bytes(shape.vertices).buffer), 3));
      g.setIndex(new THREE.BufferAttribute(new Uint32Array(bytes(shape.faces).buffer), 1));
      g.computeVertexNormals();
      object = new THREE.Mesh(g, m);
    } else if (shape.format === 'stl') {
      const g = new THREE.STLLoader().parse(bytes(shape.data).buffer);
      g.computeVertexNormals();
      object = new THREE.Mesh(g, m);
    } else {
      const text = new TextDecoder().decode(bytes(shape.data));
      if (shape.format === 'dae') {
        // A URDF mesh's coordinates are the link frame's (z up, as the
        // model is): the turn three.js gives a Z_UP file to make it y-up
        // is undone (this world keeps z up); the file's unit is kept.
        object = new THREE.ColladaLoader().parse(text, '').scene;
        object.quaternion.set(0, 0, 0, 1);
      }
      if (shape.format === 'obj') object = new THREE.OBJLoader().parse(text);
    }
    const wrapper = new THREE.Group();
    wrapper.scale.set(shape.scale[0], shape.scale[1], shape.scale[2]);
    wrapper.add(object);
    return wrapper;
  }

  function placed(shape) {
    const object = meshOf(shape);
    const holder = new THREE.Group();
    holder.position.set(shape.pos[0], shape.pos[1], shape.pos[2]);
    holder.quaternion.set(shape.quat[1], shape.quat[2], shape.quat[3], shape.quat[0]);
    holder.add(object);
    return holder;
  }

  const world = new THREE.Group();
  scene.add(world);
  const grid = new THREE.GridHelper(D.grid.size, D.grid.divisions, 0x9a9a94, 0xcfcfc8);
  grid.rotation.x = Math.PI / 2;  // the ground plane z = 0, z up
  world.add(grid);
  world.add(new THREE.AxesHelper(0.2 * extent));
  for (const s of D.ground) world.add(placed(s));

  const bodies = D.bodies.map((b) => {
    const group = new THREE.Group();
    group.name = b.name;
    for (const s of b.shapes) group.add(placed(s));
    scene.add(group);
    return group;
  });

  // Joint markers: the anchor and each axis, on the body the scene gives them in.
  const markerMaterial = new THREE.LineBasicMaterial({ color: 0xd9480f });
  const anchorGeometry = new THREE.SphereBufferGeometry(0.008 * extent, 12, 8);
  const anchorMaterial = new THREE.MeshBasicMaterial({ color: 0xd9480f });
  const markers = [];
  for (const j of D.joints) {
    const parent = j.body < 0 ? world : bodies[j.body];
    const anchor = new THREE.Vector3(j.anchor[0], j.anchor[1], j.anchor[2]);
    const dot = new THREE.Mesh(anchorGeometry, anchorMaterial);
    dot.position.copy(anchor);
    const holder = new THREE.Group();
    holder.add(dot);
    for (const a of j.axes) {
      const d = new THREE.Vector3(a[0], a[1], a[2]).multiplyScalar(0.04 * extent);
      const g = new THREE.BufferGeometry().setFromPoints([anchor.clone().sub(d), anchor.clone().add(d)]);
      holder.add(new THREE.Line(g, markerMaterial));
    }
    parent.add(holder);
    markers.push(holder);
  }

  // Trails of the bodies' centres of mass.
  const trails = D.bodies.map((b, k) => {
    const p = new Float32Array(3 * N);
    for (let i = 0; i < N; ++i)
      for (let c = 0; c < 3; ++c) p[3 * i + c] = b.x ? at(i, b.x[c]) : b.fixed[c];
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(p, 3));
    const line = new THREE.Line(g, new THREE.LineBasicMaterial({ color: new THREE.Color().setHSL((k * 0.618) % 1, 0.6, 0.45) }));
    line.visible = false;
    scene.add(line);
    return line;
  });

  // ---- camera and renderer ------------------------------------------------
  const view = document.getElementById('view');
  const camera = new THREE.PerspectiveCamera(40, 1, extent * 1e-3, extent * 100);
  camera.up.set(0, 0, 1);
  const target = new THREE.Vector3(D.centre[0], D.centre[1], D.centre[2]);
  // Looking from the front right and above, far enough to hold the run's box.
  const eye = new THREE.Vector3(0.55, -0.75, 0.38).normalize().multiplyScalar(1.5 * extent);
  camera.position.copy(target).add(eye);
  camera.lookAt(target);
  let renderer = null;
  try {
    renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    renderer.setPixelRatio(window.devicePixelRatio || 1);
    view.appendChild(renderer.domElement);
  } catch (e) {
    document.getElementById('notes').insertAdjacentHTML('afterbegin',
      '<li class="warn">This browser gives no WebGL context: the bodies cannot be drawn (' + e.message + ').</li>');
  }
  let controls = null;
  if (renderer && THREE.OrbitControls) {
    controls = new THREE.OrbitControls(camera, renderer.domElement);
    controls.target.copy(target);
    controls.update();
    controls.addEventListener('change', () => draw());
  }
  function resize() {
    const w = view.clientWidth || 800, h = view.clientHeight || 600;
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
    if (renderer) renderer.setSize(w, h);
  }

  // ---- playback -------------------------------------------------------------
  const slider = document.getElementById('slider');
  const clock = document.getElementById('clock');
  const play = document.getElementById('play');
  const speed = document.getElementById('speed');
  const pick = document.getElementById('column');
  const reading = document.getElementById('reading');
  const trailBox = document.getElementById('trails');
  const jointBox = document.getElementById('joints');
  slider.max = String(N - 1);
  for (const c of D.scalars) {
    const o = document.createElement('option');
    o.value = String(c);
    o.textContent = D.columns[c];
    pick.appendChild(o);
  }
  const energy = D.columns.indexOf('energy');
  if (energy >= 0) pick.value = String(energy);

  let frame = 0, time = times[0], playing = false, last = null;
  /// The last frame at or before time t (binary search).
  function frameAt(t) {
    let lo = 0, hi = N - 1;
    if (t >= times[hi]) return hi;
    while (hi - lo > 1) {
      const mid = (lo + hi) >> 1;
      if (times[mid] <= t) lo = mid; else hi = mid;
    }
    return lo;
  }
  function pose(i) {
    D.bodies.forEach((b, k) => {
      const g = bodies[k];
      if (b.x) g.position.set(at(i, b.x[0]), at(i, b.x[1]), at(i, b.x[2]));
      else g.position.set(b.fixed[0], b.fixed[1], b.fixed[2]);
      g.quaternion.set(at(i, b.q[1]), at(i, b.q[2]), at(i, b.q[3]), at(i, b.q[0]));
      trails[k].geometry.setDrawRange(0, i + 1);
    });
  }
  function draw() {
    if (renderer) renderer.render(scene, camera);
  }
  function show(i) {
    frame = i;
    pose(i);
    slider.value = String(i);
    clock.textContent = 't = ' + times[i].toPrecision(6) + ' s  (frame ' + (i + 1) + ' of ' + N + ')';
    const c = Number(pick.value);
    reading.textContent = pick.options.length ? D.columns[c] + ' = ' + at(i, c).toPrecision(10) : '';
    draw();
    if (!playing) writeState();
  }
  /// The drawn poses, read back from the scene graph (world matrices).
  function writeState() {
    scene.updateMatrixWorld(true);
    const p = new THREE.Vector3(), q = new THREE.Quaternion(), s = new THREE.Vector3();
    const state = { t: times[frame], frame: frame, bodies: [] };
    D.bodies.forEach((b, k) => {
      bodies[k].matrixWorld.decompose(p, q, s);
      state.bodies.push({ name: b.name, position: [p.x, p.y, p.z], quaternion: [q.w, q.x, q.y, q.z] });
    });
    document.getElementById('lieflow-state').textContent = JSON.stringify(state);
  }
  function tick(now) {
    if (!playing) return;
    if (last !== null) time += ((now - last) / 1000) * Number(speed.value);
    last = now;
    if (time > times[N - 1]) time = times[0];
    const i = frameAt(time);
    if (i !== frame) show(i);
    requestAnimationFrame(tick);
  }
  function setPlaying(on) {
    playing = on && N > 1;
    play.textContent = playing ? 'pause' : 'play';
    last = null;
    if (playing) requestAnimationFrame(tick);
    else writeState();
  }
  play.addEventListener('click', () => setPlaying(!playing));
  slider.addEventListener('input', () => {
    setPlaying(false);
    time = times[Number(slider.value)];
    show(Number(slider.value));
  });
  pick.addEventListener('change', () => show(frame));
  trailBox.addEventListener('change', () => {
    trails.forEach((t) => { t.visible = trailBox.checked; });
    draw();
  });
  jointBox.addEventListener('change', () => {
    markers.forEach((m) => { m.visible = jointBox.checked; });
    draw();
  });
  window.addEventListener('resize', () => { resize(); draw(); });

  resize();
  const asked = /[#&]t=([-+0-9.eE]+)/.exec(window.location.hash);
  if (asked) {
    time = Number(asked[1]);
    show(frameAt(time));
  } else {
    show(0);
    setPlaying(N > 1);
  }
})();

// noether view: draws NOETHER_RUN (host/src/view.cpp writes it) with three.js.
//
// Parameters after '#' in the page's address, over those `noether view --params` gave
// (docs/visualisation.md, "Parameters"):
//   frame=K (the K-th frame shown, from 0) or t=T (the frame shown nearest T), play=1,
//   view=inertial | barycentric | centre:NAME | frame:NAME (NAME's rotating body frame),
//   camera=x,y,z  target=x,y,z  up=x,y,z  fov=DEG (vertical),
//   trails=0, trail=N (frames), labels=0, axes=1, particles=0, hud=0, size=WxH (the picture's pixels instead
//   of the window's), flat=1 (surfaces only, unlit flat colours, no antialiasing: what the tests measure).
// The page reports what it drew in <pre id="noether-status"> as JSON (the tests read it).
'use strict';
(function () {
  const status = { ready: false, errors: [], warnings: [] };
  const statusElement = document.getElementById('noether-status');
  const publish = () => { statusElement.textContent = JSON.stringify(status); };
  window.addEventListener('error', (e) => { status.errors.push(String(e.message)); publish(); });
  const consoleError = console.error.bind(console), consoleWarn = console.warn.bind(console);
  console.error = (...a) => { status.errors.push(a.join(' ')); publish(); consoleError(...a); };
  console.warn = (...a) => { status.warnings.push(a.join(' ')); publish(); consoleWarn(...a); };

  const run = NOETHER_RUN;
  const P = new URLSearchParams(run.params);  // noether view --params, then the address's own
  new URLSearchParams(location.hash.slice(1)).forEach((value, key) => P.set(key, value));
  const flat = P.get('flat') === '1';
  const numbers = (key) => (P.has(key) ? P.get(key).split(',').map(Number) : null);

  // The run's frames: typed arrays from base64 (little-endian, as x86 and ARM hosts are).
  const buffer = (b64) => {
    const s = atob(b64), u = new Uint8Array(s.length);
    for (let i = 0; i < s.length; ++i) u[i] = s.charCodeAt(i);
    return u.buffer;
  };
  const t = new Float64Array(buffer(run.t)), frameIndex = new Uint32Array(buffer(run.frame_index));
  const F = t.length, n = run.bodies.length;
  // Run 0 is the file viewed; runs 1… are others shown with it (an ensemble's samples), at the
  // same frames, each until its own last frame.
  const runs = [{ label: run.file, frames: F, x: new Float64Array(buffer(run.x)), q: new Float32Array(buffer(run.q)) }]
    .concat((run.others || []).map((o) => ({ label: o.label, frames: o.frames, x: new Float64Array(buffer(o.x)),
                                              q: new Float32Array(buffer(o.q)) })));
  const rigidCount = run.bodies.filter((b) => b.rigid >= 0).length;
  // The recorded massless particles (run 0's): inertial positions [frame][particle][3].
  const particleCount = run.particles || 0;
  const particleX = particleCount > 0 ? new Float64Array(buffer(run.particle_x)) : new Float64Array(0);
  const byName = new Map(run.bodies.map((b, j) => [b.name, j]));

  // Colours: distinct, and in flat mode pure, so that a test can find each body's pixels.
  const palette = flat ? [0xff0000, 0x00ff00, 0x0000ff, 0xffff00, 0xff00ff, 0x00ffff, 0xff8000, 0x8000ff]
                       : [0xd9a05b, 0x6fa8dc, 0x93c47d, 0xe06666, 0xb4a7d6, 0xf6b26b, 0x76a5af, 0xc27ba0];
  const colourOf = (j, r = 0) => palette[(flat ? r * n + j : j) % palette.length];

  // The view's frame at shown frame i: origin o and rotation M (view = M (x − o)), as a
  // function giving a body's position and attitude in it.
  let viewKind = P.get('view') || 'inertial';
  const totalMass = run.bodies.reduce((s, b) => s + b.mass, 0);
  const attitude = (i, j, r = 0) => {
    const k = run.bodies[j].rigid, q = runs[r].q, a = (i * rigidCount + k) * 4;
    return k < 0 ? new THREE.Quaternion() : new THREE.Quaternion(q[a], q[a + 1], q[a + 2], q[a + 3]);
  };
  // Every run is watched from run 0's frame (its barycentre, its body).
  function frameOfView(i) {
    const x = runs[0].x;
    const origin = [0, 0, 0];  // in float64: subtracted before three.js rounds to float32
    let turn = new THREE.Quaternion();
    const [kind, name] = viewKind.split(/:(.*)/s);
    if (kind === 'barycentric') {
      for (let j = 0; j < n; ++j)
        for (let c = 0; c < 3; ++c) origin[c] += run.bodies[j].mass * x[(i * n + j) * 3 + c] / totalMass;
    } else if (kind === 'centre' || kind === 'frame') {
      const k = byName.get(name);
      for (let c = 0; c < 3; ++c) origin[c] = x[(i * n + k) * 3 + c];
      if (kind === 'frame') turn = attitude(i, k).conjugate();
    }
    const place = (y, a) => new THREE.Vector3(y[a] - origin[0], y[a + 1] - origin[1], y[a + 2] - origin[2])
      .applyQuaternion(turn);
    return {
      position: (j, r = 0) => place(runs[r].x, (i * n + j) * 3),
      particle: (p) => place(particleX, (i * particleCount + p) * 3),
      attitude: (j, r = 0) => turn.clone().multiply(attitude(i, j, r)),
    };
  }
  const frameChoices = ['inertial', 'barycentric'];
  run.bodies.forEach((b) => {
    frameChoices.push('centre:' + b.name);
    if (b.rigid >= 0) frameChoices.push('frame:' + b.name);
  });
  if (!frameChoices.includes(viewKind)) {
    console.error('view=' + viewKind + ' is not one of ' + frameChoices.join(', '));
    viewKind = 'inertial';
  }

  // three.js: renderer, scene, lights, one group per body in its body frame.
  const fixedSize = P.has('size') ? P.get('size').split('x').map(Number) : null;
  const width = () => (fixedSize ? fixedSize[0] : window.innerWidth);
  const height = () => (fixedSize ? fixedSize[1] : window.innerHeight);
  const renderer = new THREE.WebGLRenderer({ antialias: !flat, preserveDrawingBuffer: true });
  renderer.setPixelRatio(flat ? 1 : window.devicePixelRatio);
  renderer.setSize(width(), height());
  document.getElementById('view').appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(flat ? 0x000000 : 0x0b0d12);
  if (!flat) {
    scene.add(new THREE.AmbientLight(0xffffff, 0.35));
    const sun = new THREE.DirectionalLight(0xffffff, 0.9);
    sun.position.set(1, -0.6, 0.8);
    scene.add(sun);
  }
  // A surface's material: flat or lit; a ghost (another run's body) translucent.
  const surfaceMaterial = (colour, ghost, options) => {
    if (flat) return new THREE.MeshBasicMaterial(Object.assign({ color: colour }, options));
    const look = { color: colour, roughness: 0.85, metalness: 0 };
    if (ghost) Object.assign(look, { transparent: true, opacity: 0.38, depthWrite: false });
    return new THREE.MeshStandardMaterial(Object.assign(look, options));
  };

  // Run 0's bodies opaque, the other runs' translucent (in flat mode all opaque, each in a colour
  // of its own).
  function bodyObject(body, colour, ghost) {
    const group = new THREE.Group(), s = body.shape;
    const material = (c, options = {}) => surfaceMaterial(c, ghost, options);
    let size = 0;
    if (s.kind === 'polyhedron') {
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(buffer(s.vertices)), 3));
      g.setIndex(new THREE.BufferAttribute(new Uint32Array(buffer(s.faces)), 1));
      g.computeVertexNormals();
      g.computeBoundingSphere();
      group.add(new THREE.Mesh(g, material(colour, { flatShading: true })));
      size = g.boundingSphere.radius + g.boundingSphere.center.length();
    } else if (s.kind === 'ellipsoid') {
      const m = new THREE.Mesh(new THREE.SphereBufferGeometry(1, 64, 40), material(colour));
      m.scale.set(s.semi_axes[0], s.semi_axes[1], s.semi_axes[2]);
      if (s.rotation) m.quaternion.set(s.rotation[0], s.rotation[1], s.rotation[2], s.rotation[3]);
      group.add(m);
      size = Math.max(...s.semi_axes);
    } else if (s.kind === 'spheres') {
      s.centres.forEach((c, i) => {
        const m = new THREE.Mesh(new THREE.SphereBufferGeometry(s.radii[i], 32, 20), material(colour));
        m.position.set(c[0], c[1], c[2]);
        group.add(m);
        size = Math.max(size, Math.hypot(...c) + s.radii[i]);
      });
      if (!flat) {  // the rod joining them; flat pictures hold surfaces only
        const rod = new THREE.BufferGeometry().setFromPoints(s.centres.map((c) => new THREE.Vector3(c[0], c[1], c[2])));
        group.add(new THREE.Line(rod, new THREE.LineBasicMaterial({ color: colour })));
      }
    } else if (s.kind === 'sphere' || s.kind === 'field') {
      const options = s.kind === 'field' ? { wireframe: true, transparent: true, opacity: 0.45 } : {};
      group.add(new THREE.Mesh(new THREE.SphereBufferGeometry(s.radius, 48, 32), material(colour, options)));
      size = s.radius;
    } else {  // a point mass: a dot of constant size on screen
      const g = new THREE.BufferGeometry().setFromPoints([new THREE.Vector3()]);
      group.add(new THREE.Points(g, new THREE.PointsMaterial({ color: colour, size: 6, sizeAttenuation: false })));
    }
    if (body.rigid >= 0) {
      const axes = new THREE.AxesHelper(1.4 * (size || 1));
      axes.name = 'axes';
      axes.visible = P.get('axes') === '1';
      group.add(axes);
    }
    return { group, size };
  }
  const drawn = runs.map((_, r) => run.bodies.map((b, j) => bodyObject(b, colourOf(j, r), r > 0)));
  const bodies = drawn[0];
  drawn.forEach((objects) => objects.forEach((b) => scene.add(b.group)));

  // Trails: the last `trailLength` frames shown, each body's path as seen in the view's frame.
  const trailLength = Math.min(F, Number(P.get('trail') || 400));
  const trails = runs.map((_, r) => run.bodies.map((b, j) => {
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(3 * trailLength), 3));
    const line = new THREE.Line(g, new THREE.LineBasicMaterial({ color: colourOf(j, r), transparent: true,
                                                                 opacity: r > 0 ? 0.3 : 0.55 }));
    line.frustumCulled = false;
    scene.add(line);
    return line;
  }));

  // The particles: a dot each, of constant size on screen (white in flat mode: no body has it).
  const particleDots = (() => {
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(3 * particleCount), 3));
    const dots = new THREE.Points(g, new THREE.PointsMaterial({ color: flat ? 0xffffff : 0xcfd8e3, size: flat ? 3 : 2,
                                                                sizeAttenuation: false }));
    dots.frustumCulled = false;
    dots.visible = particleCount > 0;
    scene.add(dots);
    return dots;
  })();

  // The impulses: marks on the slider at the frame nearest each, and a button that goes there.
  const nearestFrame = (T) => {
    let best = 0;
    for (let i = 1; i < F; ++i) if (Math.abs(t[i] - T) < Math.abs(t[best] - T)) best = i;
    return best;
  };
  const impulses = (run.impulses || []).map((m) => ({ t: m.t, body: m.body, frame: nearestFrame(m.t) }));

  // Labels and legend.
  const labelLayer = document.getElementById('labels');
  const labels = run.bodies.map((b, j) => {
    const d = document.createElement('div');
    d.className = 'label';
    d.textContent = b.name;
    d.style.color = '#' + colourOf(j).toString(16).padStart(6, '0');
    labelLayer.appendChild(d);
    return d;
  });
  document.getElementById('legend').innerHTML = run.bodies.map((b, j) =>
    '<div><span style="background:#' + colourOf(j).toString(16).padStart(6, '0') + '"></span>' +
    b.name.replace(/[&<>]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;' }[c])) + ' — ' + b.shape.kind +
    (b.shape.inferred ? ' (of its inertia)' : '') + '</div>').join('') +
    (runs.length > 1 ? '<div>with ' + (runs.length - 1) + ' more run' + (runs.length > 2 ? 's' : '') +
                       ', translucent</div>' : '');
  document.getElementById('title').textContent = run.title;
  document.getElementById('notes').innerHTML = run.notes.map((s) => '<div></div>').join('');
  [...document.getElementById('notes').children].forEach((d, i) => { d.textContent = run.notes[i]; });

  // Camera: from the address, else one that holds every body over the whole run.
  const camera = new THREE.PerspectiveCamera(numbers('fov') ? numbers('fov')[0] : 35, width() / height(), 1, 2);
  camera.up.set(...(numbers('up') || [0, 0, 1]));
  const controls = new THREE.OrbitControls(camera, renderer.domElement);
  function fitCamera() {
    let extent = 0;
    for (let i = 0; i < F; i += Math.max(1, Math.floor(F / 500))) {
      const v = frameOfView(i);
      for (let j = 0; j < n; ++j) extent = Math.max(extent, v.position(j).length() + bodies[j].size);
    }
    extent = Math.max(extent, run.largest_body, 1e-30);
    const distance = 1.1 * extent / Math.tan((camera.fov * Math.PI / 180) / 2) / Math.min(1, camera.aspect);
    controls.target.set(0, 0, 0);
    camera.position.set(0, -0.8, 0.6).normalize().multiplyScalar(distance);
  }
  if (numbers('camera')) {
    camera.position.set(...numbers('camera'));
    controls.target.set(...(numbers('target') || [0, 0, 0]));
  } else {
    fitCamera();
  }
  controls.update();

  // The scale bar: a round length near 120 pixels at the distance of the point looked at.
  const scaleBar = document.getElementById('scale-bar'), scaleText = document.getElementById('scale-text');
  function drawScale() {
    const perPixel = 2 * camera.position.distanceTo(controls.target) * Math.tan((camera.fov * Math.PI / 180) / 2) /
                     height();
    const raw = 120 * perPixel, decade = Math.pow(10, Math.floor(Math.log10(raw)));
    const length = [5, 2, 1].map((m) => m * decade).find((l) => l <= raw);
    scaleBar.style.width = (length / perPixel).toFixed(1) + 'px';
    scaleText.textContent = Number(length.toPrecision(3)) + ' ' + run.unit_length;
  }

  // Time: the frame shown, in the run's unit and, for seconds, in hours or days.
  const timeText = document.getElementById('time');
  function describeTime(i) {
    let text = 't = ' + Number(t[i].toPrecision(8)) + ' ' + run.unit_time;
    if (run.unit_time === 's' && Math.abs(t[i]) >= 3600)
      text += Math.abs(t[i]) >= 172800 ? ' = ' + (t[i] / 86400).toFixed(3) + ' d' : ' = ' + (t[i] / 3600).toFixed(3) + ' h';
    return text + ' · frame ' + (frameIndex[i] + 1) + ' of ' + run.frames_in_file;
  }

  let current = 0;
  function show(i) {
    current = Math.max(0, Math.min(F - 1, Math.round(i)));
    const v = frameOfView(current);
    const first = Math.max(0, current - trailLength + 1);
    const kinds = [];
    for (let k = first; k <= current; ++k) kinds.push(frameOfView(k));
    runs.forEach((R, r) => {
      const here = current < R.frames;  // a run that ended (an event stopped it) is not drawn after
      drawn[r].forEach((b, j) => {
        b.group.visible = here;
        if (!here) return;
        b.group.position.copy(v.position(j, r));
        b.group.quaternion.copy(v.attitude(j, r));
      });
      const last = Math.min(current, R.frames - 1);
      trails[r].forEach((line, j) => {
        const a = line.geometry.attributes.position;
        let m = 0;
        for (let k = first; k <= last; ++k, ++m) { const p = kinds[k - first].position(j, r); a.setXYZ(m, p.x, p.y, p.z); }
        a.needsUpdate = true;
        line.geometry.setDrawRange(0, m);
        line.visible = trailsBox.checked;
      });
    });
    if (particleCount > 0) {
      const a = particleDots.geometry.attributes.position;
      for (let p = 0; p < particleCount; ++p) { const q = v.particle(p); a.setXYZ(p, q.x, q.y, q.z); }
      a.needsUpdate = true;
      particleDots.visible = particlesBox.checked;
    }
    slider.value = current;
    timeText.textContent = describeTime(current);
    render();
  }

  function render() {
    // Clipping planes around what is looked at, so that zooming in on a small body in a large
    // scene keeps depth resolution.
    const d = camera.position.distanceTo(controls.target);
    camera.near = d * 1e-3;
    camera.far = d * 1e3 + 4 * run.largest_body;
    camera.updateProjectionMatrix();
    renderer.render(scene, camera);
    const v = new THREE.Vector3();
    labels.forEach((label, j) => {
      v.copy(bodies[j].group.position).project(camera);
      const inside = labelsBox.checked && v.z < 1 && Math.abs(v.x) <= 1 && Math.abs(v.y) <= 1;
      label.classList.toggle('hidden', !inside);
      label.style.left = ((v.x + 1) / 2 * width()).toFixed(1) + 'px';
      label.style.top = ((1 - v.y) / 2 * height()).toFixed(1) + 'px';
    });
    drawScale();
    Object.assign(status, {
      frame: current, file_frame: frameIndex[current], time: t[current], frames_shown: F, view: viewKind,
      width: renderer.domElement.width, height: renderer.domElement.height, fov: camera.fov,
      camera: camera.position.toArray(), target: controls.target.toArray(), up: camera.up.toArray(),
      colours: run.bodies.map((b, j) => colourOf(j)),
      particles: particleDots.visible ? particleCount : 0, impulses,
      runs: runs.map((R, r) => ({ label: R.label, frames: R.frames, colours: run.bodies.map((b, j) => colourOf(j, r)) })),
    });
    publish();
  }

  // Controls.
  const slider = document.getElementById('slider'), play = document.getElementById('play');
  const speed = document.getElementById('speed'), frameSelect = document.getElementById('frame');
  const trailsBox = document.getElementById('trails'), labelsBox = document.getElementById('labels-on');
  const axesBox = document.getElementById('axes'), particlesBox = document.getElementById('particles');
  particlesBox.checked = P.get('particles') !== '0';
  particlesBox.parentElement.classList.toggle('hidden', particleCount === 0);
  particlesBox.addEventListener('change', () => show(current));
  const ticks = document.getElementById('impulse-frames'), jumps = document.getElementById('impulses');
  ticks.innerHTML = impulses.map(() => '<option></option>').join('');
  impulses.forEach((m, k) => {
    ticks.options[k].value = m.frame;
    const b = document.createElement('button');
    b.textContent = 'impulse on ' + m.body + ', ' + describeTime(m.frame).split(' · ')[0];
    b.title = 'go to the frame nearest the impulse (frame ' + (frameIndex[m.frame] + 1) + ' of the file)';
    b.addEventListener('click', () => show(m.frame));
    jumps.appendChild(b);
  });
  slider.max = F - 1;
  trailsBox.checked = P.get('trails') !== '0';
  labelsBox.checked = P.get('labels') !== '0';
  axesBox.checked = P.get('axes') === '1';
  frameSelect.innerHTML = frameChoices.map((c) => '<option></option>').join('');
  frameChoices.forEach((c, i) => {
    const o = frameSelect.options[i];
    o.value = c;
    o.textContent = c === 'inertial' ? 'inertial' : c === 'barycentric' ? 'barycentric'
                  : c.startsWith('centre:') ? 'centred on ' + c.slice(7) : c.slice(6) + "'s body frame";
  });
  frameSelect.value = viewKind;
  if (P.get('hud') === '0')
    ['hud', 'title', 'time', 'notes', 'legend', 'scale', 'labels'].forEach((id) => document.getElementById(id).classList.add('hidden'));

  slider.addEventListener('input', () => show(Number(slider.value)));
  trailsBox.addEventListener('change', () => show(current));
  labelsBox.addEventListener('change', render);
  axesBox.addEventListener('change', () => {
    bodies.forEach((b) => { const a = b.group.getObjectByName('axes'); if (a) a.visible = axesBox.checked; });
    render();
  });
  frameSelect.addEventListener('change', () => { viewKind = frameSelect.value; fitCamera(); controls.update(); show(current); });
  controls.addEventListener('change', render);
  window.addEventListener('resize', () => {
    camera.aspect = width() / height();
    renderer.setSize(width(), height());
    render();
  });

  let playing = false, position0 = 0, clock0 = 0;
  function tick(now) {
    if (!playing) return;
    const i = position0 + (now - clock0) / 1000 * Number(speed.value);
    show(i % F);
    requestAnimationFrame(tick);
  }
  function toggle() {
    playing = !playing;
    play.textContent = playing ? 'pause' : 'play';
    if (playing) { position0 = current; clock0 = performance.now(); requestAnimationFrame(tick); }
  }
  play.addEventListener('click', toggle);
  speed.addEventListener('change', () => { position0 = current; clock0 = performance.now(); });
  window.addEventListener('keydown', (e) => { if (e.code === 'Space' && e.target === document.body) { e.preventDefault(); toggle(); } });

  // The frame to start at: frame=K, else the one nearest t=T, else the first.
  let start = 0;
  if (P.has('frame')) start = Number(P.get('frame'));
  else if (P.has('t')) {
    const T = Number(P.get('t'));
    for (let i = 1; i < F; ++i) if (Math.abs(t[i] - T) < Math.abs(t[start] - T)) start = i;
  }
  show(start);
  status.ready = true;
  status.load_ms = performance.now();  // since the page began to load (its time origin)
  publish();
  if (P.get('play') === '1') toggle();
})();

// sscs HTML reports: the 3D view. The model is the glTF sscs export writes (render/gltf.h): a
// node per object with extras.sscs.object, per device part, per shape; a run's motion as the
// animation "run"; the vault's cameras and the run's camera as glTF cameras. three.js r111
// (Debian's libjs-three: THREE, THREE.GLTFLoader, THREE.OrbitControls as globals).
(function (root) {
  'use strict';

  function decodeBase64(text) {
    const bin = atob(text.trim());
    const bytes = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; ++i) bytes[i] = bin.charCodeAt(i);
    return bytes.buffer;
  }

  /** The world box of a node's meshes: each mesh's geometry box (computed once, shared by the
   *  meshes of one shape) turned by its world matrix. Box3.setFromObject visits every vertex. */
  function boxOf(node) {
    const box = new THREE.Box3(), part = new THREE.Box3();
    node.traverse((m) => {
      if (!m.isMesh || !m.geometry) return;
      if (!m.geometry.boundingBox) m.geometry.computeBoundingBox();
      box.union(part.copy(m.geometry.boundingBox).applyMatrix4(m.matrixWorld));
    });
    return box;
  }

  class View3D {
    /** A canvas in `container` showing the glb (base64); `onPick(name)` when an object is clicked. */
    constructor(container, glbBase64, { onPick, onTime } = {}) {
      this.container = container;
      this.onPick = onPick || (() => {});
      this.onTime = onTime || (() => {});
      this.objects = new Map();   // object name -> its node
      this.cameras = [];          // [{name, camera}]
      this.activeCamera = null;   // null: free orbit
      this.highlights = new Map();  // object name -> colour (hex number)
      this.variants = new Map();    // "material uuid|colour|clear" -> the material looking so
      this.time = 0;
      this.duration = 0;
      this.playing = false;
      this.speed = 1;
      this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
      this.renderer.setPixelRatio(Math.min(2, root.devicePixelRatio || 1));
      this.renderer.setClearColor(0xf4f5f7);
      container.appendChild(this.renderer.domElement);
      this.renderer.domElement.setAttribute('data-testid', 'view3d');
      this.scene = new THREE.Scene();
      this.scene.add(new THREE.HemisphereLight(0xffffff, 0x8d8d8d, 0.9));
      const sun = new THREE.DirectionalLight(0xffffff, 0.7);
      sun.position.set(-3, 10, 6);
      this.scene.add(sun);
      this.orbitCamera = new THREE.PerspectiveCamera(45, 1, 0.05, 5000);
      this.controls = new THREE.OrbitControls(this.orbitCamera, this.renderer.domElement);
      this.controls.addEventListener('change', () => { this.activeCamera = null; this.render(); });
      this.ready = new Promise((resolve, reject) => {
        new THREE.GLTFLoader().parse(decodeBase64(glbBase64), '', (gltf) => {
          try { this.loaded(gltf); resolve(this); } catch (e) { reject(e); }
        }, reject);
      });
      // The container gets its size once the page lays it out: follow it.
      if (root.ResizeObserver) new ResizeObserver(() => this.resize()).observe(container);
      else root.addEventListener('resize', () => this.resize());
      this.resize();
      this.pickAt = this.pickAt.bind(this);
      let down = null;
      this.renderer.domElement.addEventListener('pointerdown', (e) => { down = [e.clientX, e.clientY]; });
      this.renderer.domElement.addEventListener('pointerup', (e) => {
        if (down && Math.hypot(e.clientX - down[0], e.clientY - down[1]) < 4) this.onPick(this.pickAt(e.clientX, e.clientY));
        down = null;
      });
    }

    /** Shows another glb (base64) in place of the model (sscs serve's update in place): the
     *  renderer, camera, controls and switches stay, so the user's view does not move. */
    replaceModel(glbBase64) {
      this.ready = new Promise((resolve, reject) => {
        new THREE.GLTFLoader().parse(decodeBase64(glbBase64), '', (gltf) => {
          try {
            this.closest = null;  // (its nodes go with the old model, as the reach dots do)
            this.reach = null;
            if (this.model) {
              this.scene.remove(this.model);
              this.model.traverse((node) => {
                if (node.geometry) node.geometry.dispose();
                if (node.userData.base) node.userData.base.dispose();
              });
              for (const m of this.variants.values()) m.dispose();
              this.variants = new Map();
            }
            if (this.gridHelper) this.scene.remove(this.gridHelper);
            this.objects = new Map();
            this.cameras = [];
            this.highlights = new Map();
            this.mixer = null;
            this.action = null;
            this.duration = 0;
            this.loaded(gltf, { keepCamera: true });
            this.look();
            resolve(this);
          } catch (e) { reject(e); }
        }, reject);
      });
      return this.ready;
    }

    /** A save's changes (sscs serve): the objects of the glb (base64; "" for none) put in place
     *  of those of the same names, and the objects named in `removed` taken out. */
    patchModel(glbBase64, removed) {
      const apply = (gltf) => {
        this.clearClosest();
        this.showReach({});
        const root = this.model.children[0];
        const drop = (name) => {
          const node = this.objects.get(name);
          if (node && node.parent) node.parent.remove(node);
          this.objects.delete(name);
        };
        (removed || []).forEach(drop);
        if (gltf) {
          const nodes = [...gltf.scene.children[0].children];
          for (const node of nodes) {
            const info = node.userData && node.userData.sscs;
            if (!info || !info.object || info.part) continue;  // (the vault's cameras)
            drop(info.object);
            root.add(node);
            this.objects.set(info.object, node);
            node.traverse((m) => {
              if (!m.isMesh) return;
              m.userData.base = m.material;
              if (m.material.transparent) m.material.depthWrite = false;
            });
          }
        }
        this.model.updateMatrixWorld(true);
        this.bounds = boxOf(this.model);
        this.contentBounds = new THREE.Box3();
        for (const node of this.objects.values()) if (!node.userData.sscs.container) this.contentBounds.union(boxOf(node));
        if (this.contentBounds.isEmpty()) this.contentBounds = this.bounds;
        if (this.gridHelper) this.scene.remove(this.gridHelper);
        this.grid();
        this.look();  // (the new objects' materials as the highlights say)
        return this;
      };
      if (!glbBase64) {
        this.ready = Promise.resolve(apply(null));
        return this.ready;
      }
      this.ready = new Promise((resolve, reject) => {
        new THREE.GLTFLoader().parse(decodeBase64(glbBase64), '', (gltf) => {
          try { resolve(apply(gltf)); } catch (e) { reject(e); }
        }, reject);
      });
      return this.ready;
    }

    loaded(gltf, { keepCamera = false } = {}) {
      this.model = gltf.scene;
      this.scene.add(this.model);
      this.model.traverse((node) => {
        const info = node.userData && node.userData.sscs;
        if (info && info.object && !info.part) this.objects.set(info.object, node);
        if (node.isMesh) {
          // The model's materials stay shared (one per colour): a mesh that looks otherwise (a
          // highlight, see-through) takes a variant of its material (look()). A material per mesh
          // cost a 10,000-object vault seconds at every update (three.js sets each one up).
          node.userData.base = node.material;
          if (node.material.transparent) node.material.depthWrite = false;  // a room does not hide what it holds
        }
      });
      (gltf.cameras || []).forEach((camera) => {
        const info = camera.parent && camera.parent.userData && camera.parent.userData.sscs;
        this.cameras.push({ name: (info && info.camera) || camera.name || `camera ${this.cameras.length + 1}`, camera });
      });
      const clip = (gltf.animations || [])[0];
      if (clip) {
        this.mixer = new THREE.AnimationMixer(this.model);
        this.action = this.mixer.clipAction(clip);
        this.action.play();
        this.duration = clip.duration;
      }
      const rootInfo = this.model.children[0] && this.model.children[0].userData.sscs;
      if (rootInfo && typeof rootInfo.duration === 'number') this.duration = Math.max(this.duration, rootInfo.duration);
      this.model.updateMatrixWorld(true);
      this.bounds = boxOf(this.model);
      // What to frame first: the objects a container (a room) holds, not the room's walls.
      this.contentBounds = new THREE.Box3();
      for (const node of this.objects.values()) if (!node.userData.sscs.container) this.contentBounds.union(boxOf(node));
      if (this.contentBounds.isEmpty()) this.contentBounds = this.bounds;
      this.grid();
      this.resize();
      if (!keepCamera) this.frameAll();
      this.setTime(0);
      if (!this.looping) {
        this.looping = true;
        this.loop();
      }
      this.render();
    }

    grid() {
      const size = this.bounds.getSize(new THREE.Vector3());
      const span = Math.max(size.x, size.z, 1);
      const step = span > 60 ? 10 : 1;
      const n = Math.ceil((span * 1.2) / step);
      const grid = new THREE.GridHelper(n * step, n, 0xb0b4ba, 0xd5d8dc);
      const c = this.bounds.getCenter(new THREE.Vector3());
      grid.position.set(c.x, this.bounds.min.y - 0.001, c.z);
      this.scene.add(grid);
      this.gridHelper = grid;
    }

    resize() {
      const w = Math.max(1, this.container.clientWidth), h = Math.max(1, this.container.clientHeight);
      this.renderer.setSize(w, h);
      this.orbitCamera.aspect = w / h;
      this.orbitCamera.updateProjectionMatrix();
      this.render();
    }

    /** Looks at `box` (a THREE.Box3) from the three-quarter view sscs renders with. */
    frameBox(box) {
      if (!box || box.isEmpty()) return;
      const c = box.getCenter(new THREE.Vector3());
      const r = Math.max(box.getSize(new THREE.Vector3()).length() / 2, 0.3);
      // The narrower of the vertical and horizontal fields of view (a tall view is narrow).
      const half = Math.min((this.orbitCamera.fov * Math.PI) / 360, Math.atan(Math.tan((this.orbitCamera.fov * Math.PI) / 360) * this.orbitCamera.aspect));
      const d = r / Math.sin(half);
      const dir = new THREE.Vector3(-0.55, 0.5, 0.67).normalize();  // from -x, +z (sscs -y), up
      this.orbitCamera.position.copy(c).addScaledVector(dir, d);
      this.orbitCamera.near = Math.max(0.01, d / 1000);
      this.orbitCamera.far = d * 20 + 100;
      this.orbitCamera.updateProjectionMatrix();
      this.controls.target.copy(c);
      this.controls.update();
      this.activeCamera = null;
      this.render();
    }

    frameAll() { this.frameBox(this.contentBounds || this.bounds); }

    /** Frames the named objects (those the model has), with some of what is around them. */
    frameObjects(names) {
      const box = new THREE.Box3();
      // A room named with what it holds (an `inside` failure) is the frame of reference, not
      // the subject: the view frames the member (a drum in a hall was a 3-pixel dot).
      const nodes = names.map((n) => this.objects.get(n)).filter(Boolean);
      const members = nodes.filter((node) => !node.userData.sscs.container);
      for (const node of members.length ? members : nodes) box.union(boxOf(node));
      if (box.isEmpty()) return;
      const c = box.getCenter(new THREE.Vector3());
      box.expandByPoint(c.clone().addScalar(2.5)).expandByPoint(c.clone().addScalar(-2.5));
      this.frameBox(box);
    }

    /** The "why can't it reach" picture: `device` drawn at `closest` (a failed reach target's
     *  closest pose from the JSON report: each part node put at its pose there), a red rod from
     *  its tool to the target and a red ball on the target. `null` puts the device back. */
    showClosest(device, closest) {
      this.clearClosest();
      const object = device && closest && this.objects.get(device);
      if (!object) return;
      const saved = [];
      object.traverse((node) => {
        const info = node.userData && node.userData.sscs;
        const p = info && info.part && info.object === device && closest.parts && closest.parts[info.part];
        if (!p) return;
        saved.push([node, node.position.clone(), node.quaternion.clone()]);
        node.position.set(p[0], p[1], p[2]);
        node.quaternion.set(p[4], p[5], p[6], p[3]);  // [x, y, z, qw, qx, qy, qz]; three.js's order is x, y, z, w
      });
      // In sscs's world (z up): under the model's root node, which turns it to glTF's y up.
      const group = new THREE.Group();
      group.name = 'sscs-closest';
      const red = () => new THREE.MeshBasicMaterial({ color: 0xd62728, depthTest: false, transparent: true, opacity: 0.9 });
      const tool = new THREE.Vector3(...closest.tool), target = new THREE.Vector3(...closest.target);
      const gap = target.clone().sub(tool);
      if (gap.length() > 1e-6) {
        const rod = new THREE.Mesh(new THREE.CylinderGeometry(0.012, 0.012, gap.length(), 12), red());
        rod.position.copy(tool).addScaledVector(gap, 0.5);
        rod.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), gap.clone().normalize());
        group.add(rod);
      }
      const ball = new THREE.Mesh(new THREE.SphereGeometry(0.035, 16, 12), red());
      ball.position.copy(target);
      group.add(ball);
      for (const m of group.children) m.renderOrder = 10;  // seen through what stands in front
      this.model.children[0].add(group);
      this.closest = { device, saved, group };
      this.model.updateMatrixWorld(true);
      this.render();
    }

    /** Where devices reach: {device: [x, y, z, ...]} (world points of their tools, sscs's z up),
     *  drawn as dots, each device's its own colour; {} draws none. */
    showReach(clouds) {
      if (this.reach) {
        if (this.reach.parent) this.reach.parent.remove(this.reach);
        this.reach.traverse((n) => { if (n.geometry) n.geometry.dispose(); if (n.material) n.material.dispose(); });
        this.reach = null;
      }
      const names = Object.keys(clouds || {}).filter((n) => clouds[n] && clouds[n].length);
      if (this.model && names.length) {
        this.reach = new THREE.Group();
        this.reach.name = 'sscs-reach';
        const colours = [0x17becf, 0x9467bd, 0x2ca02c, 0xff7f0e, 0x8c564b];
        names.forEach((name, i) => {
          const geometry = new THREE.BufferGeometry();
          geometry.setAttribute('position', new THREE.Float32BufferAttribute(clouds[name], 3));
          const dots = new THREE.Points(geometry, new THREE.PointsMaterial({ color: colours[i % colours.length], size: 3, sizeAttenuation: false,
                                                                            transparent: true, opacity: 0.7, depthWrite: false }));
          dots.name = name;
          this.reach.add(dots);
        });
        this.model.children[0].add(this.reach);
        this.model.updateMatrixWorld(true);
      }
      this.render();
    }

    clearClosest() {
      if (!this.closest) return;
      for (const [node, position, quaternion] of this.closest.saved) {
        node.position.copy(position);
        node.quaternion.copy(quaternion);
      }
      const group = this.closest.group;
      if (group.parent) group.parent.remove(group);
      group.traverse((n) => {
        if (n.geometry) n.geometry.dispose();
        if (n.material) n.material.dispose();
      });
      this.closest = null;
      if (this.model) this.model.updateMatrixWorld(true);
      this.render();
    }

    /** Colours objects: {name: 0xrrggbb}; every other object loses its highlight. */
    setHighlights(map) {
      this.highlights = new Map(Object.entries(map));
      this.look();
    }

    /** Draws walls, doors and fences see-through (`on`) or solid: they hide what a room holds. */
    setXray(on) {
      this.xray = on;
      this.look();
    }

    /** Every object as the state says: its highlight, and see-through when x-rayed (a wall,
     *  door or fence not highlighted: the object a row names is drawn solid). */
    look() {
      const see = new Set(['wall', 'door', 'rollup_door', 'fence']);
      for (const [name, node] of this.objects) {
        const colour = this.highlights.get(name);
        const clear = !!this.xray && colour === undefined && (node.userData.sscs.lineage || []).some((t) => see.has(t));
        node.traverse((m) => { if (m.isMesh) m.material = this.variant(m.userData.base, colour, clear); });
      }
      this.render();
    }

    /** `base` as an object looks: a highlight's colour (lit a little from within) and see-through
     *  (`clear`), made once per material and look; `base` itself when it looks as the model says. */
    variant(base, colour, clear) {
      if (colour === undefined && !clear) return base;
      const key = `${base.uuid}|${colour}|${clear}`;
      let m = this.variants.get(key);
      if (!m) {
        m = base.clone();
        if (colour !== undefined) {
          m.color.setHex(colour);
          if (m.emissive) {
            m.emissive.setHex(colour);
            m.emissiveIntensity = 0.35;
          }
        }
        if (clear) {
          m.transparent = true;
          m.opacity = 0.2;
        }
        m.depthWrite = !m.transparent;
        this.variants.set(key, m);
      }
      return m;
    }

    /** The object under a page point, or null. */
    pickAt(x, y) {
      const rect = this.renderer.domElement.getBoundingClientRect();
      const ndc = new THREE.Vector2(((x - rect.left) / rect.width) * 2 - 1, -((y - rect.top) / rect.height) * 2 + 1);
      const ray = new THREE.Raycaster();
      ray.setFromCamera(ndc, this.camera());
      for (const hit of ray.intersectObject(this.model, true)) {
        if (hit.object.material && hit.object.material.transparent) continue;  // rooms: look through
        for (let n = hit.object; n; n = n.parent) {
          const info = n.userData && n.userData.sscs;
          if (info && info.object && !info.part) return info.object;
        }
      }
      return null;
    }

    /** The page point where an object's centre is drawn (for tests and labels), or null. */
    screenPoint(name) {
      const node = this.objects.get(name);
      if (!node) return null;
      const c = boxOf(node).getCenter(new THREE.Vector3()).project(this.camera());
      const rect = this.renderer.domElement.getBoundingClientRect();
      return { x: rect.left + ((c.x + 1) / 2) * rect.width, y: rect.top + ((1 - c.y) / 2) * rect.height };
    }

    camera() {
      if (!this.activeCamera) return this.orbitCamera;
      const cam = this.activeCamera;
      const w = this.container.clientWidth, h = this.container.clientHeight;
      if (cam.isPerspectiveCamera && h > 0 && Math.abs(cam.aspect - w / h) > 1e-6) {
        cam.aspect = w / h;
        cam.updateProjectionMatrix();
      }
      return cam;
    }

    /** Looks through the named glTF camera ('' or unknown: free orbit). */
    useCamera(name) {
      const found = this.cameras.find((c) => c.name === name);
      this.activeCamera = found ? found.camera : null;
      this.render();
    }

    /** Shows the run at time t (clamped to the run). */
    setTime(t) {
      this.time = Math.min(Math.max(0, t), this.duration);
      if (this.mixer) {
        this.action.time = Math.min(this.time, this.action.getClip().duration);
        this.mixer.update(0);
      }
      this.model && this.model.updateMatrixWorld(true);
      this.onTime(this.time);
      this.render();
    }

    /** Stops drawing and removes the canvas (the page shows another vault). */
    dispose() {
      this.disposed = true;
      this.playing = false;
      this.controls.dispose();
      this.renderer.dispose();
      this.renderer.domElement.remove();
    }

    play() { if (this.time >= this.duration) this.setTime(0); this.playing = true; this.last = null; }
    pause() { this.playing = false; }

    loop() {
      requestAnimationFrame((now) => {
        if (this.disposed) return;
        if (this.playing) {
          const dt = this.last == null ? 0 : (now - this.last) / 1000;
          const next = this.time + dt * this.speed;
          if (next >= this.duration) this.playing = false;  // before setTime: the page sees the end
          this.setTime(next);
        }
        this.last = now;
        this.loop();
      });
    }

    render() {
      if (this.holds) {
        this.pending = true;
        return;
      }
      if (this.model && !this.disposed) this.renderer.render(this.scene, this.camera());
    }

    /** Draws nothing until release(), then once: a page rebuilt around this view (sscs serve)
     *  changes it many times, and a frame of a large vault takes a software renderer 0.3 s. */
    hold() { this.holds = (this.holds || 0) + 1; }

    release() {
      this.holds = Math.max(0, (this.holds || 0) - 1);
      if (!this.holds && this.pending) {
        this.pending = false;
        this.render();
      }
    }
  }

  root.SSCS = Object.assign(root.SSCS || {}, { View3D, decodeBase64 });
})(typeof globalThis !== 'undefined' ? globalThis : this);

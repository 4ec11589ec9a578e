/* pair2scene scene viewer: reads the binary glTF (GLB) embedded in this page and draws
   it with WebGL 1: flat shading, one directional light over the viewer's shoulder plus
   ambient, mouse and touch orbit, a clickable object list. No external resources.

   For tests and tools it exposes window.viewer (bounds, select, ...), sets
   window.viewerReady = true after the first frame is drawn and window.viewerError to a
   message when the page cannot show the scene. */
(function () {
  "use strict";

  // ------------------------------------------------------------------ 4x4 matrices
  // Column-major arrays of 16 numbers, as glTF and WebGL store them.

  function identity() {
    return [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1];
  }

  function multiply(a, b) {
    const out = new Array(16);
    for (let c = 0; c < 4; c++) {
      for (let r = 0; r < 4; r++) {
        let s = 0;
        for (let k = 0; k < 4; k++) s += a[k * 4 + r] * b[c * 4 + k];
        out[c * 4 + r] = s;
      }
    }
    return out;
  }

  function fromTRS(t, q, s) {
    const n = Math.hypot(q[0], q[1], q[2], q[3]) || 1;
    const x = q[0] / n, y = q[1] / n, z = q[2] / n, w = q[3] / n;
    const xx = x * x, yy = y * y, zz = z * z;
    const xy = x * y, xz = x * z, yz = y * z, wx = w * x, wy = w * y, wz = w * z;
    return [
      (1 - 2 * (yy + zz)) * s[0], 2 * (xy + wz) * s[0], 2 * (xz - wy) * s[0], 0,
      2 * (xy - wz) * s[1], (1 - 2 * (xx + zz)) * s[1], 2 * (yz + wx) * s[1], 0,
      2 * (xz + wy) * s[2], 2 * (yz - wx) * s[2], (1 - 2 * (xx + yy)) * s[2], 0,
      t[0], t[1], t[2], 1,
    ];
  }

  /** The inverse transpose of m's upper 3x3 (row-major 9 numbers), for normals. */
  function normalMatrix(m) {
    const a = m[0], b = m[4], c = m[8];
    const d = m[1], e = m[5], f = m[9];
    const g = m[2], h = m[6], i = m[10];
    const A = e * i - f * h, B = -(d * i - f * g), C = d * h - e * g;
    const det = a * A + b * B + c * C;
    const k = det === 0 ? 0 : 1 / det;
    // rows of the inverse transpose are the cofactor rows over det
    return [
      A * k, B * k, C * k,
      -(b * i - c * h) * k, (a * i - c * g) * k, -(a * h - b * g) * k,
      (b * f - c * e) * k, -(a * f - c * d) * k, (a * e - b * d) * k,
    ];
  }

  function perspective(fovy, aspect, near, far) {
    const f = 1 / Math.tan(fovy / 2);
    const nf = 1 / (near - far);
    return [f / aspect, 0, 0, 0, 0, f, 0, 0, 0, 0, (far + near) * nf, -1, 0, 0, 2 * far * near * nf, 0];
  }

  function sub(a, b) {
    return [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
  }
  function cross(a, b) {
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
  }
  function dot(a, b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  }
  function normalize(a) {
    const n = Math.hypot(a[0], a[1], a[2]) || 1;
    return [a[0] / n, a[1] / n, a[2] / n];
  }

  function lookAt(eye, target, up) {
    const z = normalize(sub(eye, target));
    const x = normalize(cross(up, z));
    const y = cross(z, x);
    return [x[0], y[0], z[0], 0, x[1], y[1], z[1], 0, x[2], y[2], z[2], 0,
      -dot(x, eye), -dot(y, eye), -dot(z, eye), 1];
  }

  // ------------------------------------------------------------------ GLB reading

  const GLB_MAGIC = 0x46546c67; // "glTF"
  const CHUNK_JSON = 0x4e4f534a;
  const CHUNK_BIN = 0x004e4942;
  const COMPONENTS = {
    5120: [1, "getInt8", 127], 5121: [1, "getUint8", 255],
    5122: [2, "getInt16", 32767], 5123: [2, "getUint16", 65535],
    5125: [4, "getUint32", 0], 5126: [4, "getFloat32", 0],
  };
  const WIDTHS = { SCALAR: 1, VEC2: 2, VEC3: 3, VEC4: 4, MAT2: 4, MAT3: 9, MAT4: 16 };

  function base64Bytes(text) {
    const raw = atob(text.replace(/\s+/g, ""));
    const out = new Uint8Array(raw.length);
    for (let i = 0; i < raw.length; i++) out[i] = raw.charCodeAt(i);
    return out;
  }

  /** {json, buffers}: the glTF document of a GLB and its buffers as Uint8Arrays. */
  function parseGlb(bytes) {
    const dv = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
    if (bytes.byteLength < 20 || dv.getUint32(0, true) !== GLB_MAGIC) throw new Error("not a GLB file");
    if (dv.getUint32(4, true) !== 2) throw new Error("GLB version " + dv.getUint32(4, true) + " is not 2");
    const total = Math.min(dv.getUint32(8, true), bytes.byteLength);
    let at = 12, json = null, bin = null;
    while (at + 8 <= total) {
      const length = dv.getUint32(at, true), type = dv.getUint32(at + 4, true);
      if (at + 8 + length > total) throw new Error("GLB chunk runs past the file");
      const data = bytes.subarray(at + 8, at + 8 + length);
      if (type === CHUNK_JSON && json === null) json = JSON.parse(new TextDecoder("utf-8").decode(data));
      else if (type === CHUNK_BIN && bin === null) bin = data;
      at += 8 + length + ((4 - (length % 4)) % 4);
    }
    if (json === null) throw new Error("GLB has no JSON chunk");
    if (json.extensionsRequired && json.extensionsRequired.length) {
      throw new Error("the GLB needs glTF extensions: " + json.extensionsRequired.join(", "));
    }
    const buffers = (json.buffers || []).map(function (b, i) {
      if (b.uri === undefined) {
        if (i !== 0 || bin === null) throw new Error("buffer " + i + " has no data");
        return bin;
      }
      const m = /^data:[^,]*;base64,(.*)$/.exec(b.uri);
      if (!m) throw new Error("buffer " + i + ": external files are not supported");
      return base64Bytes(m[1]);
    });
    return { json: json, buffers: buffers };
  }

  function readComponents(gltf, buffers, viewIndex, offset, count, width, componentType, normalized) {
    const info = COMPONENTS[componentType];
    if (!info) throw new Error("unknown component type " + componentType);
    const size = info[0], getter = info[1], scale = normalized ? info[2] : 0;
    const view = gltf.bufferViews[viewIndex];
    const buf = buffers[view.buffer];
    const stride = view.byteStride || size * width;
    const start = (view.byteOffset || 0) + (offset || 0);
    const end = count > 0 ? start + stride * (count - 1) + size * width : start;
    if (end > (view.byteOffset || 0) + view.byteLength || end > buf.byteLength) {
      throw new Error("accessor runs past its buffer view");
    }
    const out = new Float64Array(count * width);
    const dv = new DataView(buf.buffer, buf.byteOffset, buf.byteLength);
    for (let i = 0; i < count; i++) {
      const at = start + i * stride;
      for (let j = 0; j < width; j++) {
        let v = dv[getter](at + j * size, true);
        if (scale) v = Math.max(v / scale, -1);
        out[i * width + j] = v;
      }
    }
    return out;
  }

  /** The values of accessor ``index`` as a flat Float64Array (count * width). */
  function readAccessor(gltf, buffers, index) {
    const acc = gltf.accessors[index];
    const width = WIDTHS[acc.type];
    if (!width) throw new Error("unknown accessor type " + acc.type);
    let out = acc.bufferView === undefined
      ? new Float64Array(acc.count * width)
      : readComponents(gltf, buffers, acc.bufferView, acc.byteOffset, acc.count, width,
        acc.componentType, acc.normalized);
    if (acc.sparse) {
      const sp = acc.sparse;
      const at = readComponents(gltf, buffers, sp.indices.bufferView, sp.indices.byteOffset,
        sp.count, 1, sp.indices.componentType, false);
      const values = readComponents(gltf, buffers, sp.values.bufferView, sp.values.byteOffset,
        sp.count, width, acc.componentType, acc.normalized);
      for (let i = 0; i < sp.count; i++) {
        for (let j = 0; j < width; j++) out[at[i] * width + j] = values[i * width + j];
      }
    }
    return out;
  }

  /** Triangle-list vertex indices of a primitive (mode 4, 5 or 6), or null. */
  function triangleIndices(prim, indices, vertexCount) {
    const mode = prim.mode === undefined ? 4 : prim.mode;
    const idx = indices || Array.from({ length: vertexCount }, function (_, i) { return i; });
    if (mode === 4) return idx;
    const out = [];
    if (mode === 5) {
      for (let i = 0; i + 2 < idx.length; i++) {
        if (i % 2 === 0) out.push(idx[i], idx[i + 1], idx[i + 2]);
        else out.push(idx[i + 1], idx[i], idx[i + 2]);
      }
      return out;
    }
    if (mode === 6) {
      for (let i = 1; i + 1 < idx.length; i++) out.push(idx[0], idx[i], idx[i + 1]);
      return out;
    }
    return null; // points and lines are not drawn
  }

  function materialColor(gltf, prim) {
    const mat = prim.material === undefined ? null : (gltf.materials || [])[prim.material];
    const pbr = mat && mat.pbrMetallicRoughness;
    const f = (pbr && pbr.baseColorFactor) || [1, 1, 1, 1];
    return [f[0], f[1], f[2], f[3] === undefined ? 1 : f[3]];
  }

  function emptyBounds() {
    return { min: [Infinity, Infinity, Infinity], max: [-Infinity, -Infinity, -Infinity] };
  }
  function growBounds(b, x, y, z) {
    if (x < b.min[0]) b.min[0] = x;
    if (y < b.min[1]) b.min[1] = y;
    if (z < b.min[2]) b.min[2] = z;
    if (x > b.max[0]) b.max[0] = x;
    if (y > b.max[1]) b.max[1] = y;
    if (z > b.max[2]) b.max[2] = z;
  }
  function unionBounds(a, b) {
    growBounds(a, b.min[0], b.min[1], b.min[2]);
    growBounds(a, b.max[0], b.max[1], b.max[2]);
  }

  /** Every drawn piece of the default scene in world coordinates (nodes' transforms
      applied): {parts, vertices (Float32Array x y z nx ny nz per vertex), bounds}. A part
      is one primitive of one node: {node, group, first, count, color, bounds}; ``group``
      is the nearest node named by an id in ``objectIds`` (self or an ancestor), else the
      node's own name. */
  function buildScene(gltf, buffers, objectIds) {
    const nodes = gltf.nodes || [];
    let roots;
    const sceneIndex = gltf.scene === undefined ? 0 : gltf.scene;
    if (gltf.scenes && gltf.scenes[sceneIndex]) {
      roots = gltf.scenes[sceneIndex].nodes || [];
    } else {
      const child = new Set();
      nodes.forEach(function (n) { (n.children || []).forEach(function (c) { child.add(c); }); });
      roots = nodes.map(function (_, i) { return i; }).filter(function (i) { return !child.has(i); });
    }
    const parts = [];
    const chunks = [];
    let vertexTotal = 0;
    const onPath = new Set();

    function addPrimitive(prim, world, nodeName, group) {
      if (!prim.attributes || prim.attributes.POSITION === undefined) return;
      const pos = readAccessor(gltf, buffers, prim.attributes.POSITION);
      const vertexCount = pos.length / 3;
      const indices = prim.indices === undefined ? null : readAccessor(gltf, buffers, prim.indices);
      const tri = triangleIndices(prim, indices, vertexCount);
      if (tri === null || tri.length < 3) return;
      const normals = prim.attributes.NORMAL === undefined ? null
        : readAccessor(gltf, buffers, prim.attributes.NORMAL);
      const nm = normals ? normalMatrix(world) : null;
      const m = world;
      const wp = new Float64Array(pos.length); // world positions
      for (let i = 0; i < vertexCount; i++) {
        const x = pos[3 * i], y = pos[3 * i + 1], z = pos[3 * i + 2];
        wp[3 * i] = m[0] * x + m[4] * y + m[8] * z + m[12];
        wp[3 * i + 1] = m[1] * x + m[5] * y + m[9] * z + m[13];
        wp[3 * i + 2] = m[2] * x + m[6] * y + m[10] * z + m[14];
      }
      const triCount = Math.floor(tri.length / 3);
      const out = new Float32Array(triCount * 18);
      const bounds = emptyBounds();
      for (let t = 0; t < triCount; t++) {
        const ia = tri[3 * t], ib = tri[3 * t + 1], ic = tri[3 * t + 2];
        if (ia >= vertexCount || ib >= vertexCount || ic >= vertexCount) {
          throw new Error("index out of range in node " + nodeName);
        }
        let fn = null;
        if (!normals) {
          const ax = wp[3 * ia], ay = wp[3 * ia + 1], az = wp[3 * ia + 2];
          const ux = wp[3 * ib] - ax, uy = wp[3 * ib + 1] - ay, uz = wp[3 * ib + 2] - az;
          const vx = wp[3 * ic] - ax, vy = wp[3 * ic + 1] - ay, vz = wp[3 * ic + 2] - az;
          let nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
          const len = Math.hypot(nx, ny, nz);
          if (len > 0) { nx /= len; ny /= len; nz /= len; } else { nx = 0; ny = 1; nz = 0; }
          fn = [nx, ny, nz];
        }
        const corners = [ia, ib, ic];
        for (let k = 0; k < 3; k++) {
          const v = corners[k];
          const o = t * 18 + k * 6;
          out[o] = wp[3 * v];
          out[o + 1] = wp[3 * v + 1];
          out[o + 2] = wp[3 * v + 2];
          growBounds(bounds, out[o], out[o + 1], out[o + 2]);
          if (fn) {
            out[o + 3] = fn[0]; out[o + 4] = fn[1]; out[o + 5] = fn[2];
          } else {
            const x = normals[3 * v], y = normals[3 * v + 1], z = normals[3 * v + 2];
            const n = normalize([nm[0] * x + nm[1] * y + nm[2] * z, nm[3] * x + nm[4] * y + nm[5] * z,
              nm[6] * x + nm[7] * y + nm[8] * z]);
            out[o + 3] = n[0]; out[o + 4] = n[1]; out[o + 5] = n[2];
          }
        }
      }
      parts.push({ node: nodeName, group: group, first: vertexTotal, count: triCount * 3,
        color: materialColor(gltf, prim), bounds: bounds });
      chunks.push(out);
      vertexTotal += triCount * 3;
    }

    function visit(index, parent, owner) {
      if (onPath.has(index) || !nodes[index]) throw new Error("bad node graph at node " + index);
      onPath.add(index);
      const node = nodes[index];
      const local = node.matrix ? node.matrix.slice() : fromTRS(node.translation || [0, 0, 0],
        node.rotation || [0, 0, 0, 1], node.scale || [1, 1, 1]);
      const world = multiply(parent, local);
      const name = node.name === undefined ? "node_" + index : String(node.name);
      if (objectIds.has(name)) owner = name;
      if (node.mesh !== undefined) {
        const mesh = gltf.meshes[node.mesh];
        (mesh.primitives || []).forEach(function (prim) {
          addPrimitive(prim, world, name, owner === null ? name : owner);
        });
      }
      (node.children || []).forEach(function (c) { visit(c, world, owner); });
      onPath.delete(index);
    }

    roots.forEach(function (r) { visit(r, identity(), null); });
    const vertices = new Float32Array(vertexTotal * 6);
    let at = 0;
    chunks.forEach(function (c) { vertices.set(c, at); at += c.length; });
    const bounds = emptyBounds();
    parts.forEach(function (p) { unionBounds(bounds, p.bounds); });
    return { parts: parts, vertices: vertices, bounds: bounds };
  }

  // ------------------------------------------------------------------ WebGL

  const VERTEX_SHADER = [
    "attribute vec3 aPosition;",
    "attribute vec3 aNormal;",
    "uniform mat4 uViewProjection;",
    "varying vec3 vNormal;",
    "varying vec3 vPosition;",
    "void main() {",
    "  vNormal = aNormal;",
    "  vPosition = aPosition;",
    "  gl_Position = uViewProjection * vec4(aPosition, 1.0);",
    "}",
  ].join("\n");

  // Linear colour lit by ambient + one directional light, the normal turned to the
  // viewer (double-sided, whatever the winding), then encoded as sRGB.
  const FRAGMENT_SHADER = [
    "precision mediump float;",
    "uniform vec4 uColor;",
    "uniform vec3 uLight;",
    "uniform vec3 uEye;",
    "uniform float uMode;", // 0 plain, 1 selected, 2 dimmed, 3 flat id colour
    "varying vec3 vNormal;",
    "varying vec3 vPosition;",
    "void main() {",
    "  if (uMode > 2.5) { gl_FragColor = uColor; return; }",
    "  vec3 n = normalize(vNormal);",
    "  if (dot(n, uEye - vPosition) < 0.0) n = -n;",
    "  float diffuse = max(dot(n, uLight), 0.0);",
    "  vec3 c = uColor.rgb * (0.38 + 0.62 * diffuse);",
    "  if (uMode > 1.5) {",
    "    float l = dot(c, vec3(0.2126, 0.7152, 0.0722));",
    "    c = mix(c, vec3(l), 0.65) * 0.8;",
    "  } else if (uMode > 0.5) {",
    "    c = mix(c, vec3(1.0, 0.62, 0.05), 0.45) + vec3(0.06, 0.04, 0.0);",
    "  }",
    "  gl_FragColor = vec4(pow(clamp(c, 0.0, 1.0), vec3(1.0 / 2.2)), uColor.a);",
    "}",
  ].join("\n");

  function compile(gl, type, source) {
    const s = gl.createShader(type);
    gl.shaderSource(s, source);
    gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error("shader: " + gl.getShaderInfoLog(s));
    return s;
  }

  function makeProgram(gl) {
    const p = gl.createProgram();
    gl.attachShader(p, compile(gl, gl.VERTEX_SHADER, VERTEX_SHADER));
    gl.attachShader(p, compile(gl, gl.FRAGMENT_SHADER, FRAGMENT_SHADER));
    gl.bindAttribLocation(p, 0, "aPosition");
    gl.bindAttribLocation(p, 1, "aNormal");
    gl.linkProgram(p);
    if (!gl.getProgramParameter(p, gl.LINK_STATUS)) throw new Error("program: " + gl.getProgramInfoLog(p));
    const u = {};
    ["uViewProjection", "uColor", "uLight", "uEye", "uMode"].forEach(function (n) {
      u[n] = gl.getUniformLocation(p, n);
    });
    return { program: p, uniforms: u };
  }

  // ------------------------------------------------------------------ the page

  const STRUCTURE = /^(wall|door|window)_/;
  const BACKGROUND = [0.925, 0.935, 0.95];
  const FOV = (45 * Math.PI) / 180;

  function Viewer(canvas, info, model) {
    const gl = canvas.getContext("webgl", { antialias: true, alpha: false, preserveDrawingBuffer: true });
    if (!gl) throw new Error("this browser gives no WebGL context");
    this.gl = gl;
    this.canvas = canvas;
    this.info = info;
    this.model = model;
    this.selected = null;
    this.cutaway = true;
    this.frames = 0;
    this.prog = makeProgram(gl);
    this.vbo = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, this.vbo);
    gl.bufferData(gl.ARRAY_BUFFER, model.vertices, gl.STATIC_DRAW);
    this.pickTarget = null;

    // groups: name -> {parts, bounds}
    this.groups = new Map();
    const self = this;
    model.parts.forEach(function (p, i) {
      p.index = i;
      if (!self.groups.has(p.group)) self.groups.set(p.group, { parts: [], bounds: emptyBounds() });
      const g = self.groups.get(p.group);
      g.parts.push(p);
      unionBounds(g.bounds, p.bounds);
    });
    const floor = this.groups.get("floor");
    const b = floor ? floor.bounds : model.bounds;
    this.roomCenter = [(b.min[0] + b.max[0]) / 2, (b.min[1] + b.max[1]) / 2, (b.min[2] + b.max[2]) / 2];
    this.resetView();
  }

  Viewer.prototype.resetView = function () {
    const b = this.model.bounds;
    const size = sub(b.max, b.min);
    const radius = Math.max(0.5 * Math.hypot(size[0], size[1], size[2]), 0.1);
    this.target = [(b.min[0] + b.max[0]) / 2, b.min[1] + 0.3 * size[1], (b.min[2] + b.max[2]) / 2];
    this.yaw = Math.PI / 5;
    this.pitch = (42 * Math.PI) / 180;
    this.radius = radius;
    const aspect = this.canvas.clientWidth / Math.max(this.canvas.clientHeight, 1) || 1;
    const half = Math.min(FOV / 2, Math.atan(Math.tan(FOV / 2) * aspect));
    this.distance = radius / Math.sin(half);
    this.requestDraw();
  };

  Viewer.prototype.eye = function () {
    const cp = Math.cos(this.pitch);
    return [this.target[0] + this.distance * cp * Math.sin(this.yaw),
      this.target[1] + this.distance * Math.sin(this.pitch),
      this.target[2] + this.distance * cp * Math.cos(this.yaw)];
  };

  Viewer.prototype.matrices = function () {
    const eye = this.eye();
    const w = this.canvas.width, h = this.canvas.height;
    const view = lookAt(eye, this.target, [0, 1, 0]);
    const near = Math.max(this.distance - 2 * this.radius, this.distance * 0.02, 0.01);
    const far = this.distance + 3 * this.radius;
    const proj = perspective(FOV, w / Math.max(h, 1), near, far);
    // the light: from above and behind the viewer's right shoulder, in world coordinates
    const fwd = normalize(sub(this.target, eye));
    const right = normalize(cross(fwd, [0, 1, 0]));
    const up = cross(right, fwd);
    const l = normalize([
      -fwd[0] * 0.55 + up[0] * 0.7 + right[0] * 0.35,
      -fwd[1] * 0.55 + up[1] * 0.7 + right[1] * 0.35,
      -fwd[2] * 0.55 + up[2] * 0.7 + right[2] * 0.35]);
    return { eye: eye, viewProjection: multiply(proj, view), light: l };
  };

  /** Whether a wall piece stands between the viewer and the room (hidden in cutaway). */
  Viewer.prototype.hidden = function (part, eye) {
    if (!this.cutaway || !STRUCTURE.test(part.node)) return false;
    const b = part.bounds, c = this.roomCenter;
    const dx = (b.min[0] + b.max[0]) / 2 - c[0], dz = (b.min[2] + b.max[2]) / 2 - c[2];
    return dx * (eye[0] - c[0]) + dz * (eye[2] - c[2]) > 0;
  };

  Viewer.prototype.resize = function () {
    const dpr = window.devicePixelRatio || 1;
    const w = Math.max(1, Math.round(this.canvas.clientWidth * dpr));
    const h = Math.max(1, Math.round(this.canvas.clientHeight * dpr));
    if (this.canvas.width !== w || this.canvas.height !== h) {
      this.canvas.width = w;
      this.canvas.height = h;
    }
  };

  Viewer.prototype.requestDraw = function () {
    if (this.pending) return;
    this.pending = true;
    const self = this;
    window.requestAnimationFrame(function () {
      self.pending = false;
      self.draw();
    });
  };

  Viewer.prototype.bindVertices = function () {
    const gl = this.gl;
    gl.bindBuffer(gl.ARRAY_BUFFER, this.vbo);
    gl.enableVertexAttribArray(0);
    gl.enableVertexAttribArray(1);
    gl.vertexAttribPointer(0, 3, gl.FLOAT, false, 24, 0);
    gl.vertexAttribPointer(1, 3, gl.FLOAT, false, 24, 12);
  };

  Viewer.prototype.draw = function () {
    const gl = this.gl, u = this.prog.uniforms;
    this.resize();
    const m = this.matrices();
    gl.viewport(0, 0, this.canvas.width, this.canvas.height);
    gl.clearColor(BACKGROUND[0], BACKGROUND[1], BACKGROUND[2], 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.enable(gl.DEPTH_TEST);
    gl.depthFunc(gl.LEQUAL);
    gl.disable(gl.CULL_FACE);
    gl.useProgram(this.prog.program);
    this.bindVertices();
    gl.uniformMatrix4fv(u.uViewProjection, false, new Float32Array(m.viewProjection));
    gl.uniform3fv(u.uLight, m.light);
    gl.uniform3fv(u.uEye, m.eye);
    const selected = this.selected;
    const self = this;
    const parts = this.model.parts;
    parts.forEach(function (p) {
      if (self.hidden(p, m.eye)) return;
      const mode = selected === null ? 0 : (p.group === selected ? 1 : 2);
      gl.uniform4f(u.uColor, p.color[0], p.color[1], p.color[2], 1);
      gl.uniform1f(u.uMode, mode);
      gl.drawArrays(gl.TRIANGLES, p.first, p.count);
    });
    if (selected !== null && this.groups.has(selected)) {
      // the selected object's hidden parts show through what stands in front of it
      gl.enable(gl.BLEND);
      gl.blendFunc(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA);
      gl.depthFunc(gl.GREATER);
      gl.depthMask(false);
      this.groups.get(selected).parts.forEach(function (p) {
        gl.uniform4f(u.uColor, p.color[0], p.color[1], p.color[2], 0.35);
        gl.uniform1f(u.uMode, 1);
        gl.drawArrays(gl.TRIANGLES, p.first, p.count);
      });
      gl.depthMask(true);
      gl.depthFunc(gl.LEQUAL);
      gl.disable(gl.BLEND);
    }
    this.frames += 1;
    if (!window.viewerReady) {
      window.viewerReady = true;
      document.body.setAttribute("data-viewer-ready", "true");
    }
  };

  /** The group under canvas pixel (x, y) in CSS pixels, or null: the scene drawn once
      more, each part in a colour that encodes its index. */
  Viewer.prototype.pick = function (x, y) {
    const gl = this.gl, u = this.prog.uniforms;
    const w = this.canvas.width, h = this.canvas.height;
    if (!this.pickTarget || this.pickTarget.w !== w || this.pickTarget.h !== h) {
      if (this.pickTarget) {
        gl.deleteFramebuffer(this.pickTarget.fb);
        gl.deleteTexture(this.pickTarget.tex);
        gl.deleteRenderbuffer(this.pickTarget.depth);
      }
      const tex = gl.createTexture();
      gl.bindTexture(gl.TEXTURE_2D, tex);
      gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA, w, h, 0, gl.RGBA, gl.UNSIGNED_BYTE, null);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
      const depth = gl.createRenderbuffer();
      gl.bindRenderbuffer(gl.RENDERBUFFER, depth);
      gl.renderbufferStorage(gl.RENDERBUFFER, gl.DEPTH_COMPONENT16, w, h);
      const fb = gl.createFramebuffer();
      gl.bindFramebuffer(gl.FRAMEBUFFER, fb);
      gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, tex, 0);
      gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.DEPTH_ATTACHMENT, gl.RENDERBUFFER, depth);
      this.pickTarget = { fb: fb, tex: tex, depth: depth, w: w, h: h };
    }
    const m = this.matrices();
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.pickTarget.fb);
    gl.viewport(0, 0, w, h);
    gl.clearColor(0, 0, 0, 0);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.enable(gl.DEPTH_TEST);
    gl.disable(gl.BLEND);
    gl.useProgram(this.prog.program);
    this.bindVertices();
    gl.uniformMatrix4fv(u.uViewProjection, false, new Float32Array(m.viewProjection));
    gl.uniform1f(u.uMode, 3);
    const self = this;
    this.model.parts.forEach(function (p) {
      if (self.hidden(p, m.eye)) return;
      const id = p.index + 1;
      gl.uniform4f(u.uColor, (id & 255) / 255, ((id >> 8) & 255) / 255, ((id >> 16) & 255) / 255, 1);
      gl.drawArrays(gl.TRIANGLES, p.first, p.count);
    });
    const dpr = w / Math.max(this.canvas.clientWidth, 1);
    const px = new Uint8Array(4);
    gl.readPixels(Math.floor(x * dpr), h - 1 - Math.floor(y * dpr), 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    this.requestDraw();
    const id = px[0] + (px[1] << 8) + (px[2] << 16);
    return id > 0 && id <= this.model.parts.length ? this.model.parts[id - 1].group : null;
  };

  // ------------------------------------------------------------------ controls

  function attachControls(viewer, onPick) {
    const canvas = viewer.canvas;
    const pointers = new Map();
    let drag = null;

    function pan(dx, dy) {
      const eye = viewer.eye();
      const fwd = normalize(sub(viewer.target, eye));
      const right = normalize(cross(fwd, [0, 1, 0]));
      const up = cross(right, fwd);
      const k = (2 * viewer.distance * Math.tan(FOV / 2)) / Math.max(canvas.clientHeight, 1);
      for (let i = 0; i < 3; i++) viewer.target[i] += (-dx * right[i] + dy * up[i]) * k;
    }
    function zoom(factor) {
      viewer.distance = Math.min(Math.max(viewer.distance * factor, viewer.radius * 0.05), viewer.radius * 30);
    }

    canvas.addEventListener("pointerdown", function (e) {
      canvas.setPointerCapture(e.pointerId);
      pointers.set(e.pointerId, [e.clientX, e.clientY]);
      const panning = e.button === 2 || e.button === 1 || e.shiftKey;
      drag = { mode: panning ? "pan" : "rotate", moved: 0, button: e.button, pinch: null };
      e.preventDefault();
    });
    canvas.addEventListener("pointermove", function (e) {
      if (!pointers.has(e.pointerId) || drag === null) return;
      const last = pointers.get(e.pointerId);
      const dx = e.clientX - last[0], dy = e.clientY - last[1];
      pointers.set(e.pointerId, [e.clientX, e.clientY]);
      drag.moved += Math.abs(dx) + Math.abs(dy);
      if (pointers.size >= 2) {
        const [a, b] = Array.from(pointers.values());
        const span = Math.hypot(a[0] - b[0], a[1] - b[1]);
        if (drag.pinch !== null && span > 0) zoom(drag.pinch / span);
        drag.pinch = span;
        pan(dx / 2, dy / 2);
      } else if (drag.mode === "pan") {
        pan(dx, dy);
      } else {
        viewer.yaw -= dx * 0.008;
        viewer.pitch = Math.min(Math.max(viewer.pitch + dy * 0.008, -1.45), 1.55);
      }
      viewer.requestDraw();
    });
    function end(e) {
      if (!pointers.has(e.pointerId)) return;
      pointers.delete(e.pointerId);
      if (drag && pointers.size === 0) {
        if (drag.moved < 4 && drag.button === 0 && e.type === "pointerup") {
          const r = canvas.getBoundingClientRect();
          onPick(viewer.pick(e.clientX - r.left, e.clientY - r.top));
        }
        drag = null;
      } else if (drag) {
        drag.pinch = null;
      }
    }
    canvas.addEventListener("pointerup", end);
    canvas.addEventListener("pointercancel", end);
    canvas.addEventListener("contextmenu", function (e) { e.preventDefault(); });
    canvas.addEventListener("wheel", function (e) {
      e.preventDefault();
      const unit = e.deltaMode === 1 ? 16 : e.deltaMode === 2 ? 400 : 1;
      zoom(Math.exp(e.deltaY * unit * 0.0012));
      viewer.requestDraw();
    }, { passive: false });
    canvas.addEventListener("dblclick", function () { viewer.resetView(); });
    window.addEventListener("resize", function () { viewer.requestDraw(); });
  }

  function showError(message) {
    window.viewerError = message;
    const status = document.getElementById("status");
    if (status) {
      status.textContent = "Cannot show the scene: " + message;
      status.className = "error";
    }
    console.error("pair2scene viewer: " + message);
  }

  function start() {
    const info = JSON.parse(document.getElementById("scene-info").textContent);
    const glb = parseGlb(base64Bytes(document.getElementById("scene-glb").textContent));
    const ids = new Set(info.objects.map(function (o) { return o.id; }));
    const model = buildScene(glb.json, glb.buffers, ids);
    if (model.parts.length === 0) throw new Error("the scene has nothing to draw");
    const canvas = document.getElementById("view");
    const viewer = new Viewer(canvas, info, model);

    const items = Array.from(document.querySelectorAll("#objects li[data-id]"));
    const status = document.getElementById("status");
    function select(id) {
      viewer.selected = id !== null && viewer.groups.has(id) ? id : null;
      items.forEach(function (li) {
        const on = li.getAttribute("data-id") === viewer.selected;
        li.classList.toggle("selected", on);
        li.setAttribute("aria-selected", on ? "true" : "false");
        if (on) li.scrollIntoView({ block: "nearest" });
      });
      const o = info.objects.find(function (x) { return x.id === viewer.selected; });
      const on = o && o.support ? " (on " + o.support + ")" : "";
      status.textContent = o ? o.id + " \u2014 " + o.category + on : "";
      status.className = "";
      viewer.requestDraw();
    }
    function focus(id) {
      const g = viewer.groups.get(id);
      if (!g) return;
      const b = g.bounds;
      viewer.target = [(b.min[0] + b.max[0]) / 2, (b.min[1] + b.max[1]) / 2, (b.min[2] + b.max[2]) / 2];
      const r = 0.5 * Math.hypot(b.max[0] - b.min[0], b.max[1] - b.min[1], b.max[2] - b.min[2]);
      viewer.distance = Math.max(r * 4, viewer.radius * 0.3);
      viewer.requestDraw();
    }
    items.forEach(function (li) {
      const id = li.getAttribute("data-id");
      if (!viewer.groups.has(id)) li.classList.add("nomesh");
      li.addEventListener("click", function () { select(viewer.selected === id ? null : id); });
      li.addEventListener("dblclick", function () { select(id); focus(id); });
      li.addEventListener("keydown", function (e) {
        if (e.key === "Enter" || e.key === " ") { e.preventDefault(); select(viewer.selected === id ? null : id); }
      });
    });
    const filter = document.getElementById("filter");
    if (filter) {
      filter.addEventListener("input", function () {
        const q = filter.value.trim().toLowerCase();
        items.forEach(function (li) {
          li.hidden = q !== "" && li.textContent.toLowerCase().indexOf(q) < 0;
        });
      });
    }
    const cut = document.getElementById("cutaway");
    if (cut) {
      cut.checked = viewer.cutaway;
      cut.addEventListener("change", function () { viewer.cutaway = cut.checked; viewer.requestDraw(); });
    }
    const reset = document.getElementById("reset");
    if (reset) reset.addEventListener("click", function () { viewer.resetView(); });
    document.addEventListener("keydown", function (e) {
      if (e.target && (e.target.tagName === "INPUT")) return;
      if (e.key === "r" || e.key === "R") viewer.resetView();
      else if (e.key === "Escape") select(null);
      else if ((e.key === "f" || e.key === "F") && viewer.selected !== null) focus(viewer.selected);
    });
    attachControls(viewer, function (id) { select(id); });

    function copyBounds(b) {
      return { min: b.min.slice(), max: b.max.slice() };
    }
    window.viewer = {
      info: info,
      bounds: function (name) {
        if (name === undefined) return copyBounds(model.bounds);
        const g = viewer.groups.get(name);
        if (g) return copyBounds(g.bounds);
        const b = emptyBounds();
        let found = false;
        model.parts.forEach(function (p) { if (p.node === name) { unionBounds(b, p.bounds); found = true; } });
        return found ? copyBounds(b) : null;
      },
      groups: function () { return Array.from(viewer.groups.keys()); },
      nodes: function () { return Array.from(new Set(model.parts.map(function (p) { return p.node; }))); },
      select: select,
      selected: function () { return viewer.selected; },
      pick: function (x, y) { return viewer.pick(x, y); },
      frames: function () { return viewer.frames; },
      triangles: model.vertices.length / 18,
      camera: function () {
        return { yaw: viewer.yaw, pitch: viewer.pitch, distance: viewer.distance, target: viewer.target.slice() };
      },
      setCamera: function (c) {
        if (c.yaw !== undefined) viewer.yaw = c.yaw;
        if (c.pitch !== undefined) viewer.pitch = c.pitch;
        if (c.distance !== undefined) viewer.distance = c.distance;
        if (c.target !== undefined) viewer.target = c.target.slice();
        viewer.requestDraw();
      },
      redraw: function () { viewer.draw(); },
      /** CSS pixel (x, y) of a world point in the canvas. */
      project: function (p) {
        const m = viewer.matrices().viewProjection;
        const x = m[0] * p[0] + m[4] * p[1] + m[8] * p[2] + m[12];
        const y = m[1] * p[0] + m[5] * p[1] + m[9] * p[2] + m[13];
        const w = m[3] * p[0] + m[7] * p[1] + m[11] * p[2] + m[15];
        return [(x / w + 1) / 2 * canvas.clientWidth, (1 - y / w) / 2 * canvas.clientHeight];
      },
    };
    window.viewerBounds = copyBounds(model.bounds);
    viewer.requestDraw();
  }

  function boot() {
    try {
      start();
    } catch (err) {
      showError(err && err.message ? err.message : String(err));
    }
  }
  if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", boot);
  else boot();
})();

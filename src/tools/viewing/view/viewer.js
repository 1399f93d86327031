/* rigidref view: draws the simulation embedded in <script id="rigidref-data"> (format
   "rigidref-view", version 1). Plain script, no modules and no dependencies, because the Rust side
   pastes it verbatim into one self-contained page that must work offline.
   Sections: helpers, data checking, plots, 3D view (WebGL), 2D view (canvas), controls, start. */
(function () {
  'use strict';

  const FORMAT = 'rigidref-view';
  const VERSION = 1;
  // Split so that the Rust side's str::replace of the data placeholder cannot touch this file.
  const DATA_PLACEHOLDER = '__RIGIDREF' + '_DATA__';
  const SERIES_COLORS = ['#1f77b4', '#d62728', '#2ca02c', '#ff7f0e', '#9467bd',
    '#8c564b', '#e377c2', '#17becf', '#7f7f7f', '#bcbd22'];
  const BODY_COLORS_3D = [[0.86, 0.47, 0.26], [0.30, 0.55, 0.85], [0.40, 0.70, 0.36],
    [0.80, 0.36, 0.55], [0.62, 0.52, 0.82], [0.86, 0.72, 0.30], [0.36, 0.72, 0.75], [0.60, 0.60, 0.62]];

  // ---------------------------------------------------------------- helpers

  function byId(id) { return document.getElementById(id); }

  function reportError(message) {
    if (typeof window.rigidrefRecordError === 'function') window.rigidrefRecordError(message);
    else console.error(message);
  }

  function dataError(message) {
    const error = new Error(message);
    error.isDataError = true;
    return error;
  }

  function makeElement(tag, className, text) {
    const element = document.createElement(tag);
    if (className) element.className = className;
    if (text !== undefined) element.textContent = text;
    return element;
  }

  function clamp(v, lo, hi) { return v < lo ? lo : v > hi ? hi : v; }

  // Keeps receiving a drag outside the element; a synthetic event has no active pointer to capture.
  function capturePointer(element, event) {
    try { element.setPointerCapture(event.pointerId); } catch (e) { /* not a live pointer */ }
  }

  // 4-6 significant digits, exponent form for very small or large magnitudes.
  function formatNumber(v, digits) {
    digits = digits || 5;
    if (typeof v !== 'number') return '–';
    if (!isFinite(v)) return String(v);
    if (v === 0) return '0';
    const a = Math.abs(v);
    if (a >= 1e-3 && a < Math.pow(10, digits)) return v.toPrecision(digits);
    return v.toExponential(digits - 1);
  }

  function formatVector(values, digits) {
    return '(' + values.map((v) => formatNumber(v, digits).padStart(digits + 7)).join(',') + ')';
  }

  // A "nice" tick spacing (1, 2 or 5 times a power of ten) giving about `count` intervals.
  function niceStep(span, count) {
    if (!(span > 0) || !isFinite(span)) return 1;
    const raw = span / Math.max(1, count);
    const power = Math.pow(10, Math.floor(Math.log10(raw)));
    const m = raw / power;
    return (m < 1.5 ? 1 : m < 3 ? 2 : m < 7 ? 5 : 10) * power;
  }

  function linearTicks(lo, hi, count) {
    const step = niceStep(hi - lo, count);
    const ticks = [];
    const first = Math.ceil(lo / step - 1e-9);
    for (let k = first; k * step <= hi + step * 1e-9 && ticks.length < 50; k++) ticks.push(k === 0 ? 0 : k * step);
    return { ticks, step };
  }

  function formatTick(v, step) {
    if (v === 0) return '0';
    const a = Math.abs(v);
    if (a >= 1e5 || a < 1e-3) {
      const digits = clamp(Math.floor(Math.log10(a)) - Math.floor(Math.log10(step) + 1e-9), 0, 4);
      return v.toExponential(digits).replace('e+', 'e');
    }
    return v.toFixed(clamp(-Math.floor(Math.log10(step) + 1e-9), 0, 8));
  }

  // Ticks of a log axis: decades, thinned on long ranges, with 2 and 5 on short ones.
  function logTicks(lo, hi) {
    const e0 = Math.floor(Math.log10(lo)), e1 = Math.ceil(Math.log10(hi));
    const ticks = [];
    const every = Math.max(1, Math.ceil((e1 - e0) / 5));
    const mantissas = e1 - e0 <= 2 ? [1, 2, 5] : [1];
    for (let e = e0; e <= e1; e++) {
      if ((e - e0) % every !== 0) continue;
      for (const m of mantissas) {
        const v = m * Math.pow(10, e);
        if (v >= lo * 0.999 && v <= hi * 1.001) ticks.push(v);
      }
    }
    return ticks;
  }

  function formatLogTick(v) {
    const e = Math.floor(Math.log10(v) + 1e-9);
    if (e >= -2 && e <= 3) return String(Number(v.toPrecision(3)));
    const m = Math.round(v / Math.pow(10, e));
    return (m === 1 ? '' : m + '·') + '1e' + e;
  }

  function escapeForTitle(text) { return String(text).replace(/\s+/g, ' '); }

  // ---------------------------------------------------------------- data checking

  function readEmbeddedData() {
    const element = byId('rigidref-data');
    if (!element) throw dataError('the page has no rigidref-data element');
    const text = element.textContent;
    if (text.trim() === DATA_PLACEHOLDER) throw dataError('the page template was not filled in (no data)');
    if (text.trim() === '') throw dataError('the data element is empty');
    try {
      return JSON.parse(text);
    } catch (e) {
      throw dataError('the data is not JSON (' + e.message + ')');
    }
  }

  function requireArray(value, what) {
    if (!Array.isArray(value)) throw dataError(what + ' is missing or not a list');
    return value;
  }

  function checkNumbers(values, what) {
    for (let i = 0; i < values.length; i++) {
      if (typeof values[i] !== 'number' || !isFinite(values[i])) throw dataError(what + '[' + i + '] is not a finite number');
    }
  }

  // Builds one mesh's GPU-ready arrays: a flat-shaded triangle list (position and face normal per
  // corner, so no shared vertices smooth the lighting) and the "feature" edges, where the faces
  // meet at more than 30 degrees, which outline boxes that would otherwise merge when stacked.
  function buildMeshGeometry(vertices, triangles, what) {
    requireArray(vertices, what + '.vertices');
    requireArray(triangles, what + '.triangles');
    if (vertices.length % 3 !== 0 || vertices.length === 0) throw dataError(what + '.vertices must hold x,y,z triples');
    if (triangles.length % 3 !== 0) throw dataError(what + '.triangles must hold i,j,k triples');
    checkNumbers(vertices, what + '.vertices');
    const nv = vertices.length / 3, nt = triangles.length / 3;
    for (let i = 0; i < triangles.length; i++) {
      const k = triangles[i];
      if (!Number.isInteger(k) || k < 0 || k >= nv) throw dataError(what + '.triangles[' + i + '] = ' + k + ' is not a vertex index (0..' + (nv - 1) + ')');
    }
    const corners = new Float32Array(nt * 18);
    const faceNormals = new Float64Array(nt * 3);
    let radius = 0;
    for (let v = 0; v < nv; v++) {
      radius = Math.max(radius, Math.hypot(vertices[3 * v], vertices[3 * v + 1], vertices[3 * v + 2]));
    }
    for (let t = 0; t < nt; t++) {
      const a = 3 * triangles[3 * t], b = 3 * triangles[3 * t + 1], c = 3 * triangles[3 * t + 2];
      const ux = vertices[b] - vertices[a], uy = vertices[b + 1] - vertices[a + 1], uz = vertices[b + 2] - vertices[a + 2];
      const wx = vertices[c] - vertices[a], wy = vertices[c + 1] - vertices[a + 1], wz = vertices[c + 2] - vertices[a + 2];
      let nx = uy * wz - uz * wy, ny = uz * wx - ux * wz, nz = ux * wy - uy * wx;
      const length = Math.hypot(nx, ny, nz);
      if (length > 0) { nx /= length; ny /= length; nz /= length; } else { nx = 0; ny = 1; nz = 0; }
      faceNormals[3 * t] = nx; faceNormals[3 * t + 1] = ny; faceNormals[3 * t + 2] = nz;
      const corner = [a, b, c];
      for (let k = 0; k < 3; k++) {
        const o = t * 18 + k * 6;
        corners[o] = vertices[corner[k]]; corners[o + 1] = vertices[corner[k] + 1]; corners[o + 2] = vertices[corner[k] + 2];
        corners[o + 3] = nx; corners[o + 4] = ny; corners[o + 5] = nz;
      }
    }
    // Edge -> first face using it; an edge is drawn when its two faces bend (either winding).
    const firstFace = new Map();
    const edgeList = [];
    for (let t = 0; t < nt; t++) {
      for (let k = 0; k < 3; k++) {
        const p = triangles[3 * t + k], q = triangles[3 * t + (k + 1) % 3];
        if (p === q) continue;
        const key = Math.min(p, q) * nv + Math.max(p, q);
        const other = firstFace.get(key);
        if (other === undefined) { firstFace.set(key, t); continue; }
        if (other < 0) continue; // already decided
        const dot = faceNormals[3 * t] * faceNormals[3 * other] + faceNormals[3 * t + 1] * faceNormals[3 * other + 1] +
          faceNormals[3 * t + 2] * faceNormals[3 * other + 2];
        if (Math.abs(dot) < 0.866) edgeList.push(p, q);
        firstFace.set(key, -1);
      }
    }
    firstFace.forEach((face, key) => { // edges of one face only: the mesh's border
      if (face >= 0) edgeList.push(Math.floor(key / nv), key % nv);
    });
    const edges = new Float32Array(edgeList.length * 3);
    for (let e = 0; e < edgeList.length; e++) {
      edges[3 * e] = vertices[3 * edgeList[e]]; edges[3 * e + 1] = vertices[3 * edgeList[e] + 1]; edges[3 * e + 2] = vertices[3 * edgeList[e] + 2];
    }
    const boxMin = [Infinity, Infinity, Infinity], boxMax = [-Infinity, -Infinity, -Infinity];
    for (let v = 0; v < nv; v++) {
      for (let c = 0; c < 3; c++) {
        boxMin[c] = Math.min(boxMin[c], vertices[3 * v + c]);
        boxMax[c] = Math.max(boxMax[c], vertices[3 * v + c]);
      }
    }
    return { corners, cornerCount: nt * 3, edges, edgeVertexCount: edgeList.length, radius, triangleCount: nt, boxMin, boxMax };
  }

  // Checks the data against the schema and precomputes what drawing needs. Throws a data error
  // (one line, naming the offending key) for anything that cannot be shown.
  function buildModel(raw) {
    if (raw === null || typeof raw !== 'object' || Array.isArray(raw)) throw dataError('the data is not a JSON object');
    if (raw.format !== FORMAT) throw dataError('"format" is ' + JSON.stringify(raw.format) + ', expected "' + FORMAT + '"');
    const warnings = [];
    if (raw.version !== VERSION) {
      if (typeof raw.version !== 'number') throw dataError('"version" is missing');
      warnings.push('data version ' + raw.version + ' is not the version ' + VERSION + ' this viewer knows; showing what it understands');
    }
    const dim = raw.dimension;
    if (dim !== 2 && dim !== 3) throw dataError('"dimension" is ' + JSON.stringify(dim) + ', expected 2 or 3');
    const bodies = requireArray(raw.bodies, '"bodies"');
    const frames = requireArray(raw.frames, '"frames"');
    if (bodies.length === 0) throw dataError('"bodies" is empty');
    if (frames.length === 0) throw dataError('"frames" is empty');
    if (Array.isArray(raw.warnings)) raw.warnings.forEach((w) => warnings.push(String(w)));

    const nb = bodies.length;
    const stride = dim === 3 ? 12 : 3, velStride = dim === 3 ? 6 : 3, rowLength = dim === 3 ? 15 : 9;
    const model = {
      dim, nb, stride, velStride, rowLength, frames, warnings,
      scene: raw.scene === undefined ? '' : String(raw.scene),
      source: raw.source === undefined ? '' : String(raw.source),
      dt: typeof raw.dt === 'number' ? raw.dt : null,
      lengthUnit: typeof raw.length_unit === 'string' ? raw.length_unit : (dim === 3 ? 'm' : 'block'),
      timeUnit: typeof raw.time_unit === 'string' ? raw.time_unit : (dim === 3 ? 's' : 'time unit'),
      names: bodies.map((b, i) => (b && b.name !== undefined ? String(b.name) : 'body ' + i)),
      masses: bodies.map((b) => (b && typeof b.mass === 'number' ? b.mass : null)),
    };
    model.velocityUnit = model.lengthUnit + '/' + model.timeUnit;
    model.omegaUnit = 'rad/' + model.timeUnit;
    model.impulseUnit = model.lengthUnit === 'm' ? 'N·s' : 'mass·' + model.lengthUnit + '/' + model.timeUnit;
    model.massUnit = model.lengthUnit === 'm' ? 'kg' : '';

    bodies.forEach((b, i) => { if (!b || typeof b !== 'object') throw dataError('bodies[' + i + '] is not an object'); });
    if (dim === 3) buildBodies3D(model, bodies); else buildBodies2D(model, bodies);
    checkFrames(model, frames, warnings);
    computeBounds(model);
    computeMaxImpulse(model);
    model.plots = normalisePlots(raw.plots, frames.length, warnings);
    return model;
  }

  function buildBodies3D(model, bodies) {
    const nb = bodies.length;
    const meshOfBody = new Int32Array(nb).fill(-1);
    const meshes = [];
    function resolveMesh(i, depth) {
      if (meshOfBody[i] >= 0) return meshOfBody[i];
      if (depth > nb) throw dataError('bodies[' + i + '].mesh.same_as goes round in a circle');
      const mesh = bodies[i].mesh;
      if (!mesh || typeof mesh !== 'object') throw dataError('bodies[' + i + '].mesh is missing');
      if (mesh.same_as !== undefined) {
        const k = mesh.same_as;
        if (!Number.isInteger(k) || k < 0 || k >= nb || k === i) throw dataError('bodies[' + i + '].mesh.same_as = ' + JSON.stringify(k) + ' is not another body\'s index');
        meshOfBody[i] = resolveMesh(k, depth + 1);
        return meshOfBody[i];
      }
      meshes.push(buildMeshGeometry(mesh.vertices, mesh.triangles, 'bodies[' + i + '].mesh'));
      meshOfBody[i] = meshes.length - 1;
      return meshOfBody[i];
    }
    for (let i = 0; i < nb; i++) resolveMesh(i, 0);
    model.meshes = meshes;
    model.meshOfBody = meshOfBody;
    model.bodiesOfMesh = meshes.map(() => []);
    for (let i = 0; i < nb; i++) model.bodiesOfMesh[meshOfBody[i]].push(i);
    model.radius = Array.from(meshOfBody, (m) => meshes[m].radius);
    model.boxMin = Array.from(meshOfBody, (m) => meshes[m].boxMin);
    model.boxMax = Array.from(meshOfBody, (m) => meshes[m].boxMax);
    model.colors = bodies.map((b, i) => {
      const c = b.color;
      if (Array.isArray(c) && c.length >= 3 && c.every((x) => typeof x === 'number')) return [clamp(c[0], 0, 1), clamp(c[1], 0, 1), clamp(c[2], 0, 1)];
      return BODY_COLORS_3D[i % BODY_COLORS_3D.length];
    });
    const radii = model.radius.slice().sort((a, b) => a - b);
    model.typicalRadius = radii[Math.floor(radii.length / 2)];
  }

  function buildBodies2D(model, bodies) {
    model.blocks = [];
    model.pinned = [];
    model.radius = [];
    model.boxMin = [];
    model.boxMax = [];
    const groups = new Map(); // colour -> the (body, block) pairs of that colour, in body order
    bodies.forEach((b, i) => {
      const blocks = requireArray(b.blocks, 'bodies[' + i + '].blocks');
      if (blocks.length % 2 !== 0) throw dataError('bodies[' + i + '].blocks must hold x,y pairs');
      checkNumbers(blocks, 'bodies[' + i + '].blocks');
      const local = Float64Array.from(blocks);
      const count = local.length / 2;
      let radius = 0;
      for (let k = 0; k < count; k++) radius = Math.max(radius, Math.hypot(local[2 * k], local[2 * k + 1]));
      model.blocks.push(local);
      model.radius.push(radius + Math.SQRT1_2);
      const lo = [Infinity, Infinity, 0], hi = [-Infinity, -Infinity, 0];
      for (let k = 0; k < 2 * count; k++) {
        lo[k % 2] = Math.min(lo[k % 2], local[k] - 0.5);
        hi[k % 2] = Math.max(hi[k % 2], local[k] + 0.5);
      }
      model.boxMin.push(count ? lo : [0, 0, 0]);
      model.boxMax.push(count ? hi : [0, 0, 0]);
      model.pinned.push(b.pinned === true);
      const colors = Array.isArray(b.colors) && b.colors.length >= 3 * count ? b.colors : null;
      for (let k = 0; k < count; k++) {
        let r, g, bl;
        if (colors) {
          r = clamp(Math.round(+colors[3 * k]) || 0, 0, 255);
          g = clamp(Math.round(+colors[3 * k + 1]) || 0, 0, 255);
          bl = clamp(Math.round(+colors[3 * k + 2]) || 0, 0, 255);
        } else if (b.pinned === true) { r = 0; g = 0; bl = 163; } else { r = 60; g = 60; bl = 60; }
        const key = (r << 16) | (g << 8) | bl;
        let group = groups.get(key);
        if (!group) { group = { style: 'rgb(' + r + ',' + g + ',' + bl + ')', body: [], block: [] }; groups.set(key, group); }
        group.body.push(i);
        group.block.push(k);
      }
    });
    model.colorGroups = Array.from(groups.values()).map((g) => ({ style: g.style, body: Int32Array.from(g.body), block: Int32Array.from(g.block) }));
    model.blockCount = model.blocks.reduce((s, b) => s + b.length / 2, 0);
  }

  function checkFrames(model, frames, warnings) {
    const nb = model.nb;
    const times = new Float64Array(frames.length);
    let badVel = 0, badPose = 0, monotone = true;
    frames.forEach((f, k) => {
      if (!f || typeof f !== 'object') throw dataError('frames[' + k + '] is not an object');
      if (typeof f.t !== 'number') throw dataError('frames[' + k + '].t is missing');
      times[k] = f.t;
      if (k > 0 && f.t < times[k - 1]) monotone = false;
      const pose = requireArray(f.pose, 'frames[' + k + '].pose');
      if (pose.length !== nb * model.stride) throw dataError('frames[' + k + '].pose has ' + pose.length + ' numbers, expected ' + nb * model.stride + ' (' + nb + ' bodies × ' + model.stride + ')');
      // Bodies beyond `present` do not exist yet (a factory run drops them later): their
      // null pose is expected, and they are not drawn.
      const present = (typeof f.present === 'number') ? Math.min(f.present, nb) : nb;
      for (let i = 0; i < pose.length; i++) {
        if (typeof pose[i] !== 'number') { pose[i] = NaN; if (i < present * model.stride) badPose++; }
      }
      if (Array.isArray(f.vel)) {
        for (let i = 0; i < f.vel.length; i++) if (typeof f.vel[i] !== 'number') f.vel[i] = NaN;
      }
      if (f.vel !== undefined && f.vel !== null && (!Array.isArray(f.vel) || f.vel.length !== nb * model.velStride)) { f.vel = null; badVel++; }
      if (f.contacts === undefined) f.contacts = null;
      if (f.contacts !== null) {
        const rows = requireArray(f.contacts, 'frames[' + k + '].contacts');
        for (let r = 0; r < rows.length; r++) {
          const row = rows[r];
          if (!Array.isArray(row) || row.length < model.rowLength) throw dataError('frames[' + k + '].contacts[' + r + '] must have ' + model.rowLength + ' numbers');
        }
      }
    });
    if (badPose) warnings.push(badPose + ' pose numbers are not numbers (NaN?): the bodies concerned are not drawn in those frames');
    if (badVel) warnings.push(badVel + ' frames have a "vel" of the wrong length: their velocities are not shown');
    if (!monotone) warnings.push('the frames\' times t decrease somewhere: playback and seeking by time may jump');
    model.times = times;
  }

  // The region every body covers over the whole run: the initial camera/fit shows all of it.
  // Each body's local bounding box, turned by its rotation (|R| times the half sizes), gives a
  // tight box for long thin bodies, which a bounding circle would not.
  function computeBounds(model) {
    const dim = model.dim, stride = model.stride;
    const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
    const R = [0, 0, 0, 0, 0, 0, 0, 0, 0];
    for (const f of model.frames) {
      const pose = f.pose;
      for (let i = 0; i < model.nb; i++) {
        const o = i * stride;
        if (dim === 3) {
          for (let k = 0; k < 9; k++) R[k] = pose[o + 3 + k];
        } else {
          const c = Math.cos(pose[o + 2]), s = Math.sin(pose[o + 2]);
          R[0] = c; R[1] = -s; R[2] = 0; R[3] = s; R[4] = c; R[5] = 0; R[6] = 0; R[7] = 0; R[8] = 1;
        }
        const bmin = model.boxMin[i], bmax = model.boxMax[i];
        for (let r = 0; r < dim; r++) {
          let centre = pose[o + r], half = 0;
          for (let c = 0; c < 3; c++) {
            centre += R[3 * r + c] * (bmin[c] + bmax[c]) / 2;
            half += Math.abs(R[3 * r + c]) * (bmax[c] - bmin[c]) / 2;
          }
          if (!isFinite(centre) || !isFinite(half)) continue;
          if (centre - half < lo[r]) lo[r] = centre - half;
          if (centre + half > hi[r]) hi[r] = centre + half;
        }
      }
    }
    for (let c = 0; c < 3; c++) {
      if (!isFinite(lo[c])) { lo[c] = -1; hi[c] = 1; }
    }
    if (dim === 2) { lo[2] = 0; hi[2] = 0; }
    model.boundsMin = lo;
    model.boundsMax = hi;
    model.sceneSize = Math.max(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1e-6);
  }

  // World impulse vector of a contact row: ln*n + lt1*t1 + lt2*t2 (3D, t2 = n x t1) or
  // ln*n + lt*t with t = (-ny, nx) (2D).
  function contactImpulse(dim, row, out) {
    if (dim === 3) {
      const nx = row[5], ny = row[6], nz = row[7], ax = row[8], ay = row[9], az = row[10];
      const bx = ny * az - nz * ay, by = nz * ax - nx * az, bz = nx * ay - ny * ax;
      const ln = row[12], l1 = row[13], l2 = row[14];
      out[0] = ln * nx + l1 * ax + l2 * bx; out[1] = ln * ny + l1 * ay + l2 * by; out[2] = ln * nz + l1 * az + l2 * bz;
    } else {
      const nx = row[4], ny = row[5], ln = row[7], lt = row[8];
      out[0] = ln * nx - lt * ny; out[1] = ln * ny + lt * nx; out[2] = 0;
    }
    return out;
  }

  function computeMaxImpulse(model) {
    let max = 0;
    const j = [0, 0, 0];
    for (const f of model.frames) {
      if (!f.contacts) continue;
      for (const row of f.contacts) {
        contactImpulse(model.dim, row, j);
        const m = Math.hypot(j[0], j[1], j[2]);
        if (m > max && isFinite(m)) max = m;
      }
    }
    model.maxImpulse = max;
    // Auto scale: the longest arrow of the run is a fifth of the scene.
    model.autoImpulseScale = max > 0 ? model.sceneSize / 5 / max : 1;
  }

  function normalisePlots(plots, frameCount, warnings) {
    if (plots === undefined || plots === null) return [];
    if (!Array.isArray(plots)) { warnings.push('"plots" is not a list: no plots shown'); return []; }
    const result = [];
    plots.forEach((p, index) => {
      if (!p || typeof p !== 'object' || !Array.isArray(p.series)) { warnings.push('plots[' + index + '] has no "series": skipped'); return; }
      const series = [];
      p.series.forEach((s, k) => {
        if (!s || !Array.isArray(s.values)) { warnings.push('plots[' + index + '].series[' + k + '] has no "values": skipped'); return; }
        if (s.values.length !== frameCount) warnings.push('plot "' + (p.title || index) + '", series "' + (s.name || k) + '" has ' + s.values.length + ' values for ' + frameCount + ' frames');
        series.push({ name: s.name === undefined ? 'series ' + k : String(s.name), values: s.values, color: SERIES_COLORS[series.length % SERIES_COLORS.length], hidden: false });
      });
      result.push({ title: p.title === undefined ? 'plot ' + index : String(p.title), unit: p.unit ? String(p.unit) : '', log: p.log === true, series });
    });
    return result;
  }

  // ---------------------------------------------------------------- frame/time lookup

  // Largest frame index whose t <= time (0 if none).
  function frameAtOrBefore(times, time) {
    let lo = 0, hi = times.length - 1;
    if (time >= times[hi]) return hi;
    if (!(time >= times[0])) return 0;
    while (hi - lo > 1) {
      const mid = (lo + hi) >> 1;
      if (times[mid] <= time) lo = mid; else hi = mid;
    }
    return lo;
  }

  function nearestFrame(times, time) {
    const k = frameAtOrBefore(times, time);
    if (k + 1 < times.length && Math.abs(times[k + 1] - time) < Math.abs(time - times[k])) return k + 1;
    return k;
  }

  // ---------------------------------------------------------------- plots

  // One small line chart per entry of "plots": a base canvas with axes and lines (redrawn only on
  // resize) under an overlay canvas with the cursor (redrawn on every frame change).
  function createPlots(container, model, onSeekTime) {
    container.textContent = '';
    if (model.plots.length > 0) {
      container.appendChild(makeElement('div', 'plots-caption', 'against time t [' + model.timeUnit + ']; click or drag in a plot to go to that time'));
    }
    if (model.plots.length === 0) {
      container.appendChild(makeElement('div', 'no-plots', 'no plots in this data'));
    }
    const panels = model.plots.map((plot) => createPlotPanel(container, plot, model, onSeekTime));
    return {
      redrawAll() { panels.forEach((p) => p.drawBase()); },
      drawCursors(frame) { panels.forEach((p) => p.drawCursor(frame)); },
      updateLegendValues(frame) { panels.forEach((p) => p.updateValues(frame)); },
    };
  }

  function seriesValue(series, k) {
    const v = series.values[k];
    return typeof v === 'number' && isFinite(v) ? v : null;
  }

  function createPlotPanel(container, plot, model, onSeekTime) {
    const times = model.times;
    const n = times.length;
    const panel = makeElement('div', 'plot');
    const title = makeElement('div', 'plot-title', plot.title);
    if (plot.unit) title.appendChild(makeElement('span', 'plot-unit', '[' + plot.unit + ']'));
    if (plot.log) title.appendChild(makeElement('span', 'plot-log', 'log scale'));
    panel.appendChild(title);
    const legend = makeElement('div', 'plot-legend');
    const valueSpans = plot.series.map((s) => {
      const item = makeElement('span', 'plot-series');
      item.title = 'click to show or hide';
      const swatch = makeElement('span', 'plot-swatch');
      swatch.style.background = s.color;
      item.appendChild(swatch);
      item.appendChild(makeElement('span', 'plot-series-name', s.name));
      const value = makeElement('span', 'plot-value', '');
      item.appendChild(value);
      item.addEventListener('click', () => {
        s.hidden = !s.hidden;
        item.classList.toggle('hidden-series', s.hidden);
        drawBase();
        drawCursor(lastFrame);
      });
      legend.appendChild(item);
      return value;
    });
    panel.appendChild(legend);
    const box = makeElement('div', 'plot-canvas-box');
    const base = document.createElement('canvas');
    const overlay = document.createElement('canvas');
    box.appendChild(base);
    box.appendChild(overlay);
    panel.appendChild(box);
    container.appendChild(panel);

    const t0 = times[0], t1 = times[n - 1] > times[0] ? times[n - 1] : times[0] + 1;
    let area = null; // plot rectangle in CSS pixels and the y mapping, set by drawBase
    let lastFrame = 0;

    function yRange() {
      let lo = Infinity, hi = -Infinity;
      for (const s of plot.series) {
        if (s.hidden) continue;
        for (let k = 0; k < s.values.length; k++) {
          const v = s.values[k];
          if (typeof v !== 'number' || !isFinite(v) || (plot.log && v <= 0)) continue;
          if (v < lo) lo = v;
          if (v > hi) hi = v;
        }
      }
      if (!(lo <= hi)) return null;
      if (plot.log) {
        if (hi / lo < 10) { const mid = Math.sqrt(hi * lo); lo = mid / 3.2; hi = mid * 3.2; }
        return { lo: lo / 1.3, hi: hi * 1.3 };
      }
      if (hi === lo) { const d = Math.abs(hi) > 0 ? Math.abs(hi) * 0.1 : 1; lo -= d; hi += d; }
      const pad = (hi - lo) * 0.06;
      return { lo: lo - pad, hi: hi + pad };
    }

    function sizeCanvas(canvas, width, height) {
      const dpr = window.devicePixelRatio || 1;
      const w = Math.max(1, Math.round(width * dpr)), h = Math.max(1, Math.round(height * dpr));
      if (canvas.width !== w || canvas.height !== h) { canvas.width = w; canvas.height = h; }
      const ctx = canvas.getContext('2d');
      ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
      return ctx;
    }

    function drawBase() {
      const width = box.clientWidth, height = box.clientHeight;
      if (width <= 0 || height <= 0) { area = null; return; }
      const ctx = sizeCanvas(base, width, height);
      sizeCanvas(overlay, width, height);
      ctx.clearRect(0, 0, width, height);
      ctx.font = '11px system-ui, sans-serif';
      const range = yRange();
      let yTicks = [], yLabels = [];
      if (range) {
        if (plot.log) { yTicks = logTicks(range.lo, range.hi); yLabels = yTicks.map(formatLogTick); }
        else { const lt = linearTicks(range.lo, range.hi, Math.max(2, Math.floor(height / 30))); yTicks = lt.ticks; yLabels = yTicks.map((v) => formatTick(v, lt.step)); }
      }
      const left = Math.ceil(Math.max(24, ...yLabels.map((l) => ctx.measureText(l).width)) + 8);
      const top = 6, right = 8, bottom = 16;
      const w = Math.max(10, width - left - right), h = Math.max(10, height - top - bottom);
      const xOf = (t) => left + (t - t0) / (t1 - t0) * w;
      let yOf = null;
      if (range) {
        if (plot.log) {
          const l0 = Math.log10(range.lo), l1 = Math.log10(range.hi);
          yOf = (v) => top + h - (Math.log10(v) - l0) / (l1 - l0) * h;
        } else {
          yOf = (v) => top + h - (v - range.lo) / (range.hi - range.lo) * h;
        }
      }
      area = { left, top, w, h, xOf, yOf };
      // axes and grid
      ctx.strokeStyle = '#e3e7eb';
      ctx.fillStyle = '#5f6b76';
      ctx.lineWidth = 1;
      ctx.textAlign = 'right';
      ctx.textBaseline = 'middle';
      yTicks.forEach((v, i) => {
        const y = Math.round(yOf(v)) + 0.5;
        ctx.beginPath(); ctx.moveTo(left, y); ctx.lineTo(left + w, y); ctx.stroke();
        ctx.fillText(yLabels[i], left - 4, y);
      });
      const xt = linearTicks(t0, t1, Math.max(2, Math.floor(w / 70)));
      ctx.textAlign = 'center';
      ctx.textBaseline = 'top';
      xt.ticks.forEach((t) => {
        const x = Math.round(xOf(t)) + 0.5;
        ctx.beginPath(); ctx.moveTo(x, top); ctx.lineTo(x, top + h); ctx.stroke();
        ctx.fillText(formatTick(t, xt.step), x, top + h + 2);
      });
      ctx.strokeStyle = '#9aa5b0';
      ctx.strokeRect(left + 0.5, top + 0.5, w, h);
      if (!range) {
        ctx.textAlign = 'center';
        ctx.textBaseline = 'middle';
        ctx.fillText(plot.log ? 'no positive values' : 'no values', left + w / 2, top + h / 2);
        return;
      }
      ctx.save();
      ctx.beginPath(); ctx.rect(left, top, w, h); ctx.clip();
      ctx.lineWidth = 1.5;
      ctx.lineJoin = 'round';
      for (const s of plot.series) {
        if (!s.hidden) drawSeries(ctx, s, xOf, yOf, w);
      }
      ctx.restore();
    }

    function usable(v) { return typeof v === 'number' && isFinite(v) && !(plot.log && v <= 0); }

    // Draws one series with gaps at nulls; with more frames than pixels, each pixel column gets a
    // min-max bar so that spikes stay visible and drawing stays fast.
    function drawSeries(ctx, s, xOf, yOf, w) {
      ctx.strokeStyle = s.color;
      ctx.fillStyle = s.color;
      const values = s.values, count = Math.min(values.length, n);
      ctx.beginPath();
      if (count > 2 * w) {
        let column = -1, lo = 0, hi = 0, open = false;
        const flush = () => {
          if (column < 0) return;
          const x = column + 0.5;
          if (open) ctx.lineTo(x, yOf(hi)); else ctx.moveTo(x, yOf(hi));
          ctx.lineTo(x, yOf(lo));
          open = true;
        };
        for (let k = 0; k < count; k++) {
          const v = values[k];
          if (!usable(v)) { flush(); column = -1; open = false; continue; }
          const c = Math.floor(xOf(times[k]));
          if (c !== column) { flush(); column = c; lo = hi = v; } else { if (v < lo) lo = v; if (v > hi) hi = v; }
        }
        flush();
        ctx.stroke();
        return;
      }
      let open = false;
      for (let k = 0; k < count; k++) {
        const v = values[k];
        if (!usable(v)) { open = false; continue; }
        const x = xOf(times[k]), y = yOf(v);
        if (open) ctx.lineTo(x, y);
        else {
          ctx.moveTo(x, y);
          // An isolated value (gaps on both sides) would draw nothing: mark it with a dot.
          if (!usable(values[k + 1])) { ctx.stroke(); ctx.beginPath(); ctx.arc(x, y, 1.8, 0, 2 * Math.PI); ctx.fill(); ctx.beginPath(); ctx.moveTo(x, y); }
        }
        open = true;
      }
      ctx.stroke();
    }

    function drawCursor(frame) {
      lastFrame = frame;
      const width = box.clientWidth, height = box.clientHeight;
      if (!area || width <= 0) return;
      const ctx = overlay.getContext('2d');
      ctx.clearRect(0, 0, width, height);
      const x = Math.round(area.xOf(times[frame])) + 0.5;
      ctx.strokeStyle = '#d32f2f';
      ctx.lineWidth = 1;
      ctx.beginPath(); ctx.moveTo(x, area.top); ctx.lineTo(x, area.top + area.h); ctx.stroke();
      if (!area.yOf) return;
      for (const s of plot.series) {
        const v = seriesValue(s, frame);
        if (s.hidden || v === null || (plot.log && v <= 0)) continue;
        ctx.fillStyle = s.color;
        ctx.beginPath(); ctx.arc(area.xOf(times[frame]), area.yOf(v), 3, 0, 2 * Math.PI); ctx.fill();
      }
    }

    function updateValues(frame) {
      plot.series.forEach((s, i) => {
        const v = seriesValue(s, frame);
        valueSpans[i].textContent = v === null ? '–' : Number.isInteger(v) && Math.abs(v) < 1e7 ? String(v) : formatNumber(v, 4);
      });
    }

    // Clicking or dragging in the chart seeks to the time under the pointer.
    let dragging = false;
    function seekToPointer(event) {
      if (!area) return;
      const rect = box.getBoundingClientRect();
      const x = event.clientX - rect.left;
      onSeekTime(t0 + clamp((x - area.left) / area.w, 0, 1) * (t1 - t0));
    }
    box.addEventListener('pointerdown', (event) => {
      dragging = true;
      capturePointer(box, event);
      seekToPointer(event);
      event.preventDefault();
    });
    box.addEventListener('pointermove', (event) => { if (dragging) seekToPointer(event); });
    const stop = () => { dragging = false; };
    box.addEventListener('pointerup', stop);
    box.addEventListener('pointercancel', stop);

    return { drawBase, drawCursor, updateValues };
  }

  // ---------------------------------------------------------------- 3D view (WebGL)

  const MESH_VERTEX_SHADER = `
    attribute vec3 aPosition;
    attribute vec3 aNormal;
    uniform mat4 uModel;
    uniform mat4 uViewProjection;
    varying vec3 vNormal;
    varying vec3 vWorld;
    void main() {
      vec4 world = uModel * vec4(aPosition, 1.0);
      vWorld = world.xyz;
      vNormal = (uModel * vec4(aNormal, 0.0)).xyz;
      gl_Position = uViewProjection * world;
    }`;

  const MESH_FRAGMENT_SHADER = `
    #ifdef GL_FRAGMENT_PRECISION_HIGH
    precision highp float;
    #else
    precision mediump float;
    #endif
    uniform vec3 uColor;
    uniform vec3 uEye;
    uniform vec3 uLightDirection;
    uniform float uHighlight;
    varying vec3 vNormal;
    varying vec3 vWorld;
    void main() {
      vec3 n = normalize(vNormal);
      // Two-sided lighting: turn the face normal toward the viewer, so a mesh with inverted or
      // mixed winding still looks solid.
      if (dot(n, uEye - vWorld) < 0.0) n = -n;
      float key = max(dot(n, uLightDirection), 0.0);
      float fill = max(dot(n, normalize(vec3(-0.5, 0.25, -0.6))), 0.0);
      vec3 color = uColor * (0.34 + 0.62 * key + 0.16 * fill);
      color = mix(color, vec3(1.0, 0.85, 0.3), uHighlight); // selected body, when there are several
      gl_FragColor = vec4(color, 1.0);
    }`;

  const LINE_VERTEX_SHADER = `
    attribute vec3 aPosition;
    attribute vec4 aColor;
    uniform mat4 uModel;
    uniform mat4 uViewProjection;
    uniform float uPointSize;
    varying vec4 vColor;
    void main() {
      vColor = aColor;
      gl_PointSize = uPointSize;
      gl_Position = uViewProjection * (uModel * vec4(aPosition, 1.0));
    }`;

  const LINE_FRAGMENT_SHADER = `
    precision mediump float;
    uniform float uRoundPoints;
    varying vec4 vColor;
    void main() {
      if (uRoundPoints > 0.5 && length(gl_PointCoord - vec2(0.5)) > 0.5) discard;
      gl_FragColor = vColor;
    }`;

  function compileProgram(gl, vertexSource, fragmentSource) {
    function compile(type, source) {
      const shader = gl.createShader(type);
      gl.shaderSource(shader, source);
      gl.compileShader(shader);
      if (!gl.getShaderParameter(shader, gl.COMPILE_STATUS) && !gl.isContextLost()) {
        throw new Error('WebGL shader does not compile: ' + gl.getShaderInfoLog(shader));
      }
      return shader;
    }
    const program = gl.createProgram();
    gl.attachShader(program, compile(gl.VERTEX_SHADER, vertexSource));
    gl.attachShader(program, compile(gl.FRAGMENT_SHADER, fragmentSource));
    gl.bindAttribLocation(program, 0, 'aPosition'); // attribute 0 always an array: no emulation
    gl.linkProgram(program);
    if (!gl.getProgramParameter(program, gl.LINK_STATUS) && !gl.isContextLost()) {
      throw new Error('WebGL program does not link: ' + gl.getProgramInfoLog(program));
    }
    const info = { program, attributes: {}, uniforms: {} };
    const na = gl.getProgramParameter(program, gl.ACTIVE_ATTRIBUTES);
    for (let i = 0; i < na; i++) { const a = gl.getActiveAttrib(program, i); info.attributes[a.name] = gl.getAttribLocation(program, a.name); }
    const nu = gl.getProgramParameter(program, gl.ACTIVE_UNIFORMS);
    for (let i = 0; i < nu; i++) { const u = gl.getActiveUniform(program, i); info.uniforms[u.name] = gl.getUniformLocation(program, u.name); }
    return info;
  }

  function perspectiveMatrix(fovY, aspect, near, far) {
    const f = 1 / Math.tan(fovY / 2), nf = 1 / (near - far);
    return [f / aspect, 0, 0, 0, 0, f, 0, 0, 0, 0, (far + near) * nf, -1, 0, 0, 2 * far * near * nf, 0];
  }

  function lookAtMatrix(eye, target, up) {
    let zx = eye[0] - target[0], zy = eye[1] - target[1], zz = eye[2] - target[2];
    let l = Math.hypot(zx, zy, zz) || 1; zx /= l; zy /= l; zz /= l;
    let xx = up[1] * zz - up[2] * zy, xy = up[2] * zx - up[0] * zz, xz = up[0] * zy - up[1] * zx;
    l = Math.hypot(xx, xy, xz) || 1; xx /= l; xy /= l; xz /= l;
    const yx = zy * xz - zz * xy, yy = zz * xx - zx * xz, yz = zx * xy - zy * xx;
    return [xx, yx, zx, 0, xy, yy, zy, 0, xz, yz, zz, 0,
      -(xx * eye[0] + xy * eye[1] + xz * eye[2]), -(yx * eye[0] + yy * eye[1] + yz * eye[2]), -(zx * eye[0] + zy * eye[1] + zz * eye[2]), 1];
  }

  function multiplyMatrices(a, b) { // column-major a*b
    const out = new Float32Array(16);
    for (let c = 0; c < 4; c++) {
      for (let r = 0; r < 4; r++) {
        out[c * 4 + r] = a[r] * b[c * 4] + a[4 + r] * b[c * 4 + 1] + a[8 + r] * b[c * 4 + 2] + a[12 + r] * b[c * 4 + 3];
      }
    }
    return out;
  }

  const IDENTITY = new Float32Array([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]);

  // Returns null when WebGL is unavailable. Each distinct mesh is uploaded once; each body is one
  // draw call with its own model matrix, so many small bodies and one big mesh are both cheap.
  function createView3D(canvas, model, ui) {
    let gl = null;
    try {
      const options = { antialias: true, alpha: false, preserveDrawingBuffer: true };
      gl = canvas.getContext('webgl', options) || canvas.getContext('experimental-webgl', options);
    } catch (e) { gl = null; }
    if (!gl) return null;

    const meshProgram = compileProgram(gl, MESH_VERTEX_SHADER, MESH_FRAGMENT_SHADER);
    const lineProgram = compileProgram(gl, LINE_VERTEX_SHADER, LINE_FRAGMENT_SHADER);
    const meshBuffers = model.meshes.map((mesh) => {
      const triangles = gl.createBuffer();
      gl.bindBuffer(gl.ARRAY_BUFFER, triangles);
      gl.bufferData(gl.ARRAY_BUFFER, mesh.corners, gl.STATIC_DRAW);
      const edges = gl.createBuffer();
      gl.bindBuffer(gl.ARRAY_BUFFER, edges);
      gl.bufferData(gl.ARRAY_BUFFER, mesh.edges.length ? mesh.edges : new Float32Array(3), gl.STATIC_DRAW);
      return { triangles, edges };
    });

    // Ground: a translucent square and a grid on y = 0, sized to the run's horizontal extent.
    const lo = model.boundsMin, hi = model.boundsMax;
    const span = Math.max(hi[0] - lo[0], hi[2] - lo[2], model.sceneSize * 0.5);
    const gridStep = niceStep(span * 1.4, 10);
    const cx = Math.round((lo[0] + hi[0]) / 2 / gridStep) * gridStep, cz = Math.round((lo[2] + hi[2]) / 2 / gridStep) * gridStep;
    const half = Math.ceil(span * 0.75 / gridStep) * gridStep;
    const gridVertices = [];
    function pushLine(list, a, b, color) { list.push(a[0], a[1], a[2], color[0], color[1], color[2], color[3], b[0], b[1], b[2], color[0], color[1], color[2], color[3]); }
    for (let k = -Math.round(half / gridStep); k <= Math.round(half / gridStep); k++) {
      const x = cx + k * gridStep, z = cz + k * gridStep;
      const major = Math.abs(Math.round(x / gridStep)) % 5 === 0;
      const majorZ = Math.abs(Math.round(z / gridStep)) % 5 === 0;
      pushLine(gridVertices, [x, 0, cz - half], [x, 0, cz + half], major ? [0.62, 0.66, 0.71, 1] : [0.78, 0.81, 0.85, 1]);
      pushLine(gridVertices, [cx - half, 0, z], [cx + half, 0, z], majorZ ? [0.62, 0.66, 0.71, 1] : [0.78, 0.81, 0.85, 1]);
    }
    const axis = gridStep; // world axes at the origin: x red, y green, z blue
    pushLine(gridVertices, [0, 0, 0], [axis, 0, 0], [0.85, 0.15, 0.15, 1]);
    pushLine(gridVertices, [0, 0, 0], [0, axis, 0], [0.15, 0.65, 0.2, 1]);
    pushLine(gridVertices, [0, 0, 0], [0, 0, axis], [0.2, 0.35, 0.9, 1]);
    const gridBuffer = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, gridBuffer);
    gl.bufferData(gl.ARRAY_BUFFER, new Float32Array(gridVertices), gl.STATIC_DRAW);
    const gridCount = gridVertices.length / 7;
    const g = [0.80, 0.83, 0.86, 0.55];
    const ground = [];
    [[-1, -1], [1, -1], [1, 1], [-1, -1], [1, 1], [-1, 1]].forEach((c) => ground.push(cx + c[0] * half, 0, cz + c[1] * half, g[0], g[1], g[2], g[3]));
    const groundBuffer = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, groundBuffer);
    gl.bufferData(gl.ARRAY_BUFFER, new Float32Array(ground), gl.STATIC_DRAW);
    const dynamicBuffer = gl.createBuffer();
    let dynamicData = new Float32Array(4096);

    const camera = { target: [0, 0, 0], distance: 1, yaw: 0.65, pitch: 0.42, fovY: 45 * Math.PI / 180 };
    const sceneRadius = 0.5 * Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]) || 1;
    const normalLength = Math.min(0.05 * model.sceneSize, 0.6 * model.typicalRadius);

    function aspect() { return Math.max(1, canvas.width) / Math.max(1, canvas.height); }

    function resetCamera() {
      camera.target = [(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2];
      camera.yaw = 0.65;
      camera.pitch = 0.42;
      const halfY = camera.fovY / 2, halfX = Math.atan(Math.tan(halfY) * aspect());
      camera.distance = sceneRadius / Math.sin(Math.min(halfY, halfX)) * 1.08;
      ui.requestViewDraw();
    }

    function eyePosition() {
      const c = Math.cos(camera.pitch), d = camera.distance, t = camera.target;
      return [t[0] + d * c * Math.sin(camera.yaw), t[1] + d * Math.sin(camera.pitch), t[2] + d * c * Math.cos(camera.yaw)];
    }

    function resizeCanvas() {
      const dpr = window.devicePixelRatio || 1;
      const w = Math.max(1, Math.round(canvas.clientWidth * dpr)), h = Math.max(1, Math.round(canvas.clientHeight * dpr));
      if (canvas.width !== w || canvas.height !== h) { canvas.width = w; canvas.height = h; }
    }

    function bindInterleaved(program, buffer) { // position (3) + colour (4) floats per vertex
      gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
      gl.enableVertexAttribArray(program.attributes.aPosition);
      gl.vertexAttribPointer(program.attributes.aPosition, 3, gl.FLOAT, false, 28, 0);
      gl.enableVertexAttribArray(program.attributes.aColor);
      gl.vertexAttribPointer(program.attributes.aColor, 4, gl.FLOAT, false, 28, 12);
    }

    // Contact points, normals, impulse arrows and (optionally) tangent frames of the current
    // frame, as one line list and one point list in a reused buffer.
    function buildContactGeometry(rows) {
      const need = rows.length * 7 * 24 + 7;
      if (dynamicData.length < need) dynamicData = new Float32Array(need * 1.5);
      const data = dynamicData;
      let o = 0;
      function vertex(x, y, z, c) { data[o++] = x; data[o++] = y; data[o++] = z; data[o++] = c[0]; data[o++] = c[1]; data[o++] = c[2]; data[o++] = c[3]; }
      const normalColor = [0.1, 0.3, 0.95, 1], impulseColor = [0.0, 0.62, 0.25, 1];
      const t1Color = [1.0, 0.55, 0.0, 1], t2Color = [0.65, 0.2, 0.85, 1];
      const scale = model.autoImpulseScale * ui.state.impulseFactor;
      const j = [0, 0, 0];
      for (const row of rows) {
        const px = row[2], py = row[3], pz = row[4], nx = row[5], ny = row[6], nz = row[7];
        vertex(px, py, pz, normalColor);
        vertex(px + nx * normalLength, py + ny * normalLength, pz + nz * normalLength, normalColor);
        contactImpulse(3, row, j);
        const jx = j[0] * scale, jy = j[1] * scale, jz = j[2] * scale;
        const length = Math.hypot(jx, jy, jz);
        if (length > 0 && isFinite(length)) {
          const ex = px + jx, ey = py + jy, ez = pz + jz;
          vertex(px, py, pz, impulseColor);
          vertex(ex, ey, ez, impulseColor);
          // arrow head: four short lines back from the tip, around the arrow's direction
          const dx = jx / length, dy = jy / length, dz = jz / length;
          let ux = dy * 0 - dz * 1, uy = dz * 0 - dx * 0, uz = dx * 1 - dy * 0; // d x y
          if (Math.hypot(ux, uy, uz) < 0.3) { ux = 0; uy = dz; uz = -dy; } // d x x
          const ul = Math.hypot(ux, uy, uz); ux /= ul; uy /= ul; uz /= ul;
          const vx = dy * uz - dz * uy, vy = dz * ux - dx * uz, vz = dx * uy - dy * ux;
          const head = Math.min(0.25 * length, 0.03 * model.sceneSize), wing = head * 0.45;
          const bx = ex - dx * head, by = ey - dy * head, bz = ez - dz * head;
          const sides = [[ux, uy, uz], [-ux, -uy, -uz], [vx, vy, vz], [-vx, -vy, -vz]];
          for (const s of sides) {
            vertex(ex, ey, ez, impulseColor);
            vertex(bx + s[0] * wing, by + s[1] * wing, bz + s[2] * wing, impulseColor);
          }
        }
        if (ui.state.showTangentFrame) {
          const ax = row[8], ay = row[9], az = row[10];
          const bx2 = ny * az - nz * ay, by2 = nz * ax - nx * az, bz2 = nx * ay - ny * ax;
          const l = normalLength * 0.8;
          vertex(px, py, pz, t1Color); vertex(px + ax * l, py + ay * l, pz + az * l, t1Color);
          vertex(px, py, pz, t2Color); vertex(px + bx2 * l, py + by2 * l, pz + bz2 * l, t2Color);
        }
      }
      const lineCount = o / 7;
      const pointColor = [0.85, 0.08, 0.08, 1];
      for (const row of rows) vertex(row[2], row[3], row[4], pointColor);
      return { data: data.subarray(0, o), lineCount, pointCount: rows.length };
    }

    function draw() {
      resizeCanvas();
      gl.viewport(0, 0, canvas.width, canvas.height);
      gl.clearColor(0.965, 0.972, 0.98, 1);
      gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
      if (gl.isContextLost()) return;
      const eye = eyePosition();
      const near = camera.distance * 0.01, far = camera.distance + 4 * (sceneRadius + half);
      const viewProjection = multiplyMatrices(perspectiveMatrix(camera.fovY, aspect(), near, far), lookAtMatrix(eye, camera.target, [0, 1, 0]));
      const frame = model.frames[ui.state.frame];
      const pose = frame.pose;
      const modelMatrix = new Float32Array(16);
      modelMatrix[15] = 1;
      function setModelMatrix(i) { // world = x + R*local, R row-major in the pose
        const o = i * 12;
        for (let k = 0; k < 12; k++) if (!isFinite(pose[o + k])) return false;
        modelMatrix[0] = pose[o + 3]; modelMatrix[1] = pose[o + 6]; modelMatrix[2] = pose[o + 9];
        modelMatrix[4] = pose[o + 4]; modelMatrix[5] = pose[o + 7]; modelMatrix[6] = pose[o + 10];
        modelMatrix[8] = pose[o + 5]; modelMatrix[9] = pose[o + 8]; modelMatrix[10] = pose[o + 11];
        modelMatrix[12] = pose[o]; modelMatrix[13] = pose[o + 1]; modelMatrix[14] = pose[o + 2];
        return true;
      }

      gl.enable(gl.DEPTH_TEST);
      gl.depthMask(true);
      gl.disable(gl.BLEND);
      gl.disable(gl.CULL_FACE);
      // Bodies, pushed slightly back so that their edge lines win the depth test.
      gl.useProgram(meshProgram.program);
      gl.uniformMatrix4fv(meshProgram.uniforms.uViewProjection, false, viewProjection);
      gl.uniform3fv(meshProgram.uniforms.uEye, eye);
      const light = [0.45, 0.8, 0.4], ll = Math.hypot(light[0], light[1], light[2]);
      gl.uniform3f(meshProgram.uniforms.uLightDirection, light[0] / ll, light[1] / ll, light[2] / ll);
      gl.enable(gl.POLYGON_OFFSET_FILL);
      gl.polygonOffset(1, 1);
      const aPos = meshProgram.attributes.aPosition, aNormal = meshProgram.attributes.aNormal;
      model.meshes.forEach((mesh, m) => {
        gl.bindBuffer(gl.ARRAY_BUFFER, meshBuffers[m].triangles);
        gl.enableVertexAttribArray(aPos);
        gl.vertexAttribPointer(aPos, 3, gl.FLOAT, false, 24, 0);
        gl.enableVertexAttribArray(aNormal);
        gl.vertexAttribPointer(aNormal, 3, gl.FLOAT, false, 24, 12);
        for (const i of model.bodiesOfMesh[m]) {
          if (!setModelMatrix(i)) continue;
          gl.uniformMatrix4fv(meshProgram.uniforms.uModel, false, modelMatrix);
          gl.uniform3fv(meshProgram.uniforms.uColor, model.colors[i]);
          gl.uniform1f(meshProgram.uniforms.uHighlight, i === ui.state.selected && model.nb > 1 ? 0.2 : 0);
          gl.drawArrays(gl.TRIANGLES, 0, mesh.cornerCount);
        }
      });
      gl.disable(gl.POLYGON_OFFSET_FILL);
      gl.disableVertexAttribArray(aNormal);

      gl.useProgram(lineProgram.program);
      const lp = lineProgram;
      gl.uniformMatrix4fv(lp.uniforms.uViewProjection, false, viewProjection);
      gl.uniform1f(lp.uniforms.uPointSize, 1);
      gl.uniform1f(lp.uniforms.uRoundPoints, 0);
      // Feature edges of every body, in a darker shade of its colour (constant colour attribute).
      gl.disableVertexAttribArray(lp.attributes.aColor);
      model.meshes.forEach((mesh, m) => {
        if (mesh.edgeVertexCount === 0) return;
        gl.bindBuffer(gl.ARRAY_BUFFER, meshBuffers[m].edges);
        gl.enableVertexAttribArray(lp.attributes.aPosition);
        gl.vertexAttribPointer(lp.attributes.aPosition, 3, gl.FLOAT, false, 12, 0);
        for (const i of model.bodiesOfMesh[m]) {
          if (!setModelMatrix(i)) continue;
          const c = model.colors[i];
          if (i === ui.state.selected && model.nb > 1) gl.vertexAttrib4f(lp.attributes.aColor, 1.0, 0.55, 0.0, 1);
          else gl.vertexAttrib4f(lp.attributes.aColor, c[0] * 0.45, c[1] * 0.45, c[2] * 0.45, 1);
          gl.uniformMatrix4fv(lp.uniforms.uModel, false, modelMatrix);
          gl.drawArrays(gl.LINES, 0, mesh.edgeVertexCount);
        }
      });
      gl.uniformMatrix4fv(lp.uniforms.uModel, false, IDENTITY);
      // Ground square (translucent, so bodies sinking below y = 0 still show) and grid.
      gl.enable(gl.BLEND);
      gl.blendFunc(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA);
      gl.depthMask(false);
      bindInterleaved(lp, groundBuffer);
      gl.drawArrays(gl.TRIANGLES, 0, 6);
      gl.depthMask(true);
      bindInterleaved(lp, gridBuffer);
      gl.drawArrays(gl.LINES, 0, gridCount);
      // Contacts on top of everything, so that contacts inside or behind bodies stay visible.
      const rows = frame.contacts;
      if (ui.state.showContacts && rows && rows.length) {
        gl.disable(gl.DEPTH_TEST);
        const geometry = buildContactGeometry(rows);
        gl.bindBuffer(gl.ARRAY_BUFFER, dynamicBuffer);
        gl.bufferData(gl.ARRAY_BUFFER, geometry.data, gl.DYNAMIC_DRAW);
        bindInterleaved(lp, dynamicBuffer);
        gl.drawArrays(gl.LINES, 0, geometry.lineCount);
        gl.uniform1f(lp.uniforms.uPointSize, (rows.length > 200 ? 4 : 6) * (window.devicePixelRatio || 1));
        gl.uniform1f(lp.uniforms.uRoundPoints, 1);
        gl.drawArrays(gl.POINTS, geometry.lineCount, geometry.pointCount);
        gl.enable(gl.DEPTH_TEST);
      }
      gl.disable(gl.BLEND);
    }

    // Mouse: left drag orbits, right or shift drag (or middle) pans, the wheel zooms.
    let drag = null;
    canvas.addEventListener('pointerdown', (event) => {
      drag = { x: event.clientX, y: event.clientY, pan: event.button === 2 || event.button === 1 || event.shiftKey };
      capturePointer(canvas, event);
      event.preventDefault();
    });
    canvas.addEventListener('pointermove', (event) => {
      if (!drag) return;
      const dx = event.clientX - drag.x, dy = event.clientY - drag.y;
      drag.x = event.clientX; drag.y = event.clientY;
      if (drag.pan) {
        const perPixel = 2 * camera.distance * Math.tan(camera.fovY / 2) / Math.max(1, canvas.clientHeight);
        const view = lookAtMatrix(eyePosition(), camera.target, [0, 1, 0]);
        for (let c = 0; c < 3; c++) camera.target[c] += (-view[c * 4] * dx + view[c * 4 + 1] * dy) * perPixel;
      } else {
        camera.yaw -= dx * 0.008;
        camera.pitch = clamp(camera.pitch + dy * 0.008, -1.55, 1.55);
      }
      ui.requestViewDraw();
    });
    const endDrag = () => { drag = null; };
    canvas.addEventListener('pointerup', endDrag);
    canvas.addEventListener('pointercancel', endDrag);
    canvas.addEventListener('contextmenu', (event) => event.preventDefault());
    canvas.addEventListener('wheel', (event) => {
      event.preventDefault();
      const delta = event.deltaY * (event.deltaMode === 1 ? 16 : event.deltaMode === 2 ? 400 : 1);
      camera.distance = clamp(camera.distance * Math.exp(delta * 0.0015), sceneRadius * 1e-3, sceneRadius * 1e3);
      ui.requestViewDraw();
    }, { passive: false });
    canvas.addEventListener('webglcontextlost', (event) => {
      event.preventDefault();
      ui.showViewMessage('The WebGL context was lost (the graphics driver was reset). Reload the page to see the 3D view again.');
    });

    resizeCanvas();
    resetCamera();
    return { draw, resetCamera, resetLabel: 'reset camera', hint: 'left drag: orbit · right or shift drag: pan · wheel: zoom' };
  }

  // ---------------------------------------------------------------- 2D view (canvas)

  // Image frame: x right, y DOWN, exactly like canvas pixels, so the mapping is a scale and an
  // offset with no flip. Blocks are batched by colour: one path per colour (per body when
  // translucent, so that overlaps show), with every block's corners computed here.
  function createView2D(canvas, model, ui) {
    const ctx = canvas.getContext('2d', { alpha: false });
    const view = { scale: 1, ox: 0, oy: 0, moved: false, width: 0, height: 0 };
    const nb = model.nb;
    const sx = new Float64Array(nb), sy = new Float64Array(nb), sc = new Float64Array(nb), ss = new Float64Array(nb);
    const visible = new Uint8Array(nb);

    function resizeCanvas() {
      const dpr = window.devicePixelRatio || 1;
      const cw = Math.max(1, canvas.clientWidth), ch = Math.max(1, canvas.clientHeight);
      const w = Math.round(cw * dpr), h = Math.round(ch * dpr);
      if (canvas.width !== w || canvas.height !== h) { canvas.width = w; canvas.height = h; }
      if (view.width && (view.width !== cw || view.height !== ch)) {
        if (!view.moved) { view.width = cw; view.height = ch; fit(); return; }
        view.ox += (cw - view.width) / 2; view.oy += (ch - view.height) / 2;
      }
      view.width = cw; view.height = ch;
    }

    function fit() {
      const lo = model.boundsMin, hi = model.boundsMax;
      const bw = (hi[0] - lo[0]) * 1.08 || 1, bh = (hi[1] - lo[1]) * 1.08 || 1;
      view.scale = Math.min(view.width / bw, view.height / bh);
      view.ox = view.width / 2 - view.scale * (lo[0] + hi[0]) / 2;
      view.oy = view.height / 2 - view.scale * (lo[1] + hi[1]) / 2;
    }

    function resetView() {
      view.moved = false;
      fit();
      ui.requestViewDraw();
    }

    // Adds block k of body b to the current path. Returns true if it added a turned square (the
    // slow kind for the canvas rasteriser) rather than an axis-aligned rect (the fast kind, used
    // when the turn moves the corners by less than 0.1 px).
    function traceBlock(b, k) {
      const local = model.blocks[b];
      const lx = local[2 * k], ly = local[2 * k + 1];
      const c = sc[b], s = ss[b];
      const cx = sx[b] + c * lx - s * ly, cy = sy[b] + s * lx + c * ly;
      if (Math.abs(s) < 0.1 || Math.abs(c) < 0.1) {
        const half = 0.5 * Math.max(Math.abs(c), Math.abs(s));
        ctx.rect(cx - half, cy - half, 2 * half, 2 * half);
        return false;
      }
      const ax = 0.5 * c, ay = 0.5 * s; // half the body's x axis; half its y axis is (-ay, ax)
      ctx.moveTo(cx - ax + ay, cy - ay - ax);
      ctx.lineTo(cx + ax + ay, cy + ay - ax);
      ctx.lineTo(cx + ax - ay, cy + ay + ax);
      ctx.lineTo(cx - ax - ay, cy - ay + ax);
      ctx.closePath();
      return true;
    }

    // The selected body's outline: block sides without a neighbouring block, in the body frame.
    const outlineCache = new Map();
    function bodyOutline(b) {
      if (outlineCache.has(b)) return outlineCache.get(b);
      const local = model.blocks[b], filled = new Set(), segments = [];
      const key = (x, y) => Math.round(x - local[0]) + ',' + Math.round(y - local[1]);
      for (let k = 0; k < local.length; k += 2) filled.add(key(local[k], local[k + 1]));
      for (let k = 0; k < local.length; k += 2) {
        const x = local[k], y = local[k + 1];
        if (!filled.has(key(x, y - 1))) segments.push(x - 0.5, y - 0.5, x + 0.5, y - 0.5);
        if (!filled.has(key(x, y + 1))) segments.push(x - 0.5, y + 0.5, x + 0.5, y + 0.5);
        if (!filled.has(key(x - 1, y))) segments.push(x - 0.5, y - 0.5, x - 0.5, y + 0.5);
        if (!filled.has(key(x + 1, y))) segments.push(x + 0.5, y - 0.5, x + 0.5, y + 0.5);
      }
      outlineCache.set(b, segments);
      return segments;
    }

    function drawArrow(x0, y0, x1, y1) {
      const dx = x1 - x0, dy = y1 - y0, length = Math.hypot(dx, dy);
      if (!(length > 0.5)) return;
      const ux = dx / length, uy = dy / length, head = Math.min(0.3 * length, 8), wing = head * 0.5;
      ctx.moveTo(x0, y0); ctx.lineTo(x1, y1);
      ctx.moveTo(x1 - ux * head - uy * wing, y1 - uy * head + ux * wing);
      ctx.lineTo(x1, y1);
      ctx.lineTo(x1 - ux * head + uy * wing, y1 - uy * head - ux * wing);
    }

    function draw() {
      resizeCanvas();
      const dpr = window.devicePixelRatio || 1;
      const W = view.width, H = view.height, S = view.scale;
      ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
      ctx.globalAlpha = 1;
      ctx.fillStyle = '#fcfcfd';
      ctx.fillRect(0, 0, W, H);
      const frame = model.frames[ui.state.frame];
      const pose = frame.pose;
      for (let i = 0; i < nb; i++) {
        const x = pose[3 * i], y = pose[3 * i + 1], th = pose[3 * i + 2];
        sx[i] = view.ox + S * x; sy[i] = view.oy + S * y;
        sc[i] = S * Math.cos(th); ss[i] = S * Math.sin(th);
        const r = S * model.radius[i];
        visible[i] = isFinite(x) && isFinite(y) && isFinite(th) && sx[i] + r >= 0 && sx[i] - r <= W && sy[i] + r >= 0 && sy[i] - r <= H ? 1 : 0;
      }
      const translucent = ui.state.opacity < 0.999;
      const outline = S >= 12;
      ctx.globalAlpha = ui.state.opacity;
      ctx.lineWidth = 1;
      ctx.strokeStyle = 'rgba(0,0,0,0.22)';
      for (const group of model.colorGroups) {
        ctx.fillStyle = group.style;
        ctx.beginPath();
        let last = -1, turned = 0;
        const bodies = group.body, blocks = group.block;
        for (let e = 0; e < bodies.length; e++) {
          const b = bodies[e];
          if (!visible[b]) continue;
          // Fill per body when translucent (overlaps then show darker), and every 16 turned
          // squares anyway: one path with thousands of turned squares fills far more slowly
          // (measured: 0.8 s against 20 ms for 32 000 blocks in Chromium's software canvas).
          if ((translucent && b !== last && last !== -1) || turned >= 16) {
            ctx.fill(); if (outline) ctx.stroke(); ctx.beginPath(); turned = 0;
          }
          last = b;
          if (traceBlock(b, blocks[e])) turned++;
        }
        ctx.fill();
        if (outline) ctx.stroke();
      }
      ctx.globalAlpha = 1;
      // centre of mass of every moving body
      const radius = clamp(0.28 * S, 1.5, 5);
      ctx.beginPath();
      for (let i = 0; i < nb; i++) {
        if (!visible[i] || model.pinned[i]) continue;
        ctx.moveTo(sx[i] + radius, sy[i]);
        ctx.arc(sx[i], sy[i], radius, 0, 2 * Math.PI);
      }
      ctx.fillStyle = '#ffffff';
      ctx.fill();
      ctx.strokeStyle = radius < 2.5 ? 'rgba(27,31,35,0.55)' : '#1b1f23';
      ctx.stroke();
      // selected body
      const sel = ui.state.selected;
      if (sel >= 0 && sel < nb && visible[sel]) {
        const seg = bodyOutline(sel), c = sc[sel], s = ss[sel];
        ctx.beginPath();
        for (let k = 0; k < seg.length; k += 4) {
          ctx.moveTo(sx[sel] + c * seg[k] - s * seg[k + 1], sy[sel] + s * seg[k] + c * seg[k + 1]);
          ctx.lineTo(sx[sel] + c * seg[k + 2] - s * seg[k + 3], sy[sel] + s * seg[k + 2] + c * seg[k + 3]);
        }
        ctx.strokeStyle = '#ff9800';
        ctx.lineWidth = 2.5;
        ctx.stroke();
        ctx.lineWidth = 1;
      }
      const rows = frame.contacts;
      if (ui.state.showContacts && rows && rows.length) drawContacts(rows);
    }

    function drawContacts(rows) {
      const S = view.scale, ox = view.ox, oy = view.oy;
      const normalLength = Math.max(0.8 * S, 6);
      const scale = model.autoImpulseScale * ui.state.impulseFactor * S;
      const j = [0, 0, 0];
      ctx.lineWidth = 1.2;
      ctx.beginPath();
      for (const row of rows) {
        const px = ox + S * row[2], py = oy + S * row[3];
        ctx.moveTo(px, py);
        ctx.lineTo(px + row[4] * normalLength, py + row[5] * normalLength);
      }
      ctx.strokeStyle = '#1a4fd8';
      ctx.stroke();
      ctx.beginPath();
      for (const row of rows) {
        contactImpulse(2, row, j);
        const px = ox + S * row[2], py = oy + S * row[3];
        drawArrow(px, py, px + j[0] * scale, py + j[1] * scale);
      }
      ctx.strokeStyle = '#00a040';
      ctx.lineWidth = 1.6;
      ctx.stroke();
      const size = clamp(0.2 * S, 2.5, 5);
      ctx.beginPath();
      for (const row of rows) ctx.rect(ox + S * row[2] - size / 2, oy + S * row[3] - size / 2, size, size);
      ctx.fillStyle = '#d81b1b';
      ctx.fill();
      ctx.lineWidth = 1;
    }

    // The topmost body with a block under the screen point, or -1.
    function bodyAt(mx, my) {
      const pose = model.frames[ui.state.frame].pose;
      const wx = (mx - view.ox) / view.scale, wy = (my - view.oy) / view.scale;
      for (let i = nb - 1; i >= 0; i--) {
        const dx = wx - pose[3 * i], dy = wy - pose[3 * i + 1];
        const r = model.radius[i];
        if (!(dx * dx + dy * dy <= r * r)) continue;
        const c = Math.cos(pose[3 * i + 2]), s = Math.sin(pose[3 * i + 2]);
        const lx = c * dx + s * dy, ly = -s * dx + c * dy; // Rot(-theta) * (p - x)
        const local = model.blocks[i];
        for (let k = 0; k < local.length; k += 2) {
          if (Math.abs(lx - local[k]) <= 0.5 && Math.abs(ly - local[k + 1]) <= 0.5) return i;
        }
      }
      return -1;
    }

    // Drag pans, a click (little movement) selects the body under the pointer, the wheel zooms
    // about the pointer.
    let drag = null;
    canvas.addEventListener('pointerdown', (event) => {
      drag = { x: event.clientX, y: event.clientY, x0: event.clientX, y0: event.clientY };
      capturePointer(canvas, event);
      event.preventDefault();
    });
    canvas.addEventListener('pointermove', (event) => {
      if (!drag) return;
      view.ox += event.clientX - drag.x;
      view.oy += event.clientY - drag.y;
      drag.x = event.clientX; drag.y = event.clientY;
      if (Math.abs(drag.x - drag.x0) + Math.abs(drag.y - drag.y0) > 3) view.moved = true;
      ui.requestViewDraw();
    });
    canvas.addEventListener('pointerup', (event) => {
      if (drag && Math.abs(event.clientX - drag.x0) + Math.abs(event.clientY - drag.y0) <= 3) {
        const rect = canvas.getBoundingClientRect();
        const hit = bodyAt(event.clientX - rect.left, event.clientY - rect.top);
        if (hit >= 0) ui.selectBody(hit);
      }
      drag = null;
    });
    canvas.addEventListener('pointercancel', () => { drag = null; });
    canvas.addEventListener('contextmenu', (event) => event.preventDefault());
    canvas.addEventListener('wheel', (event) => {
      event.preventDefault();
      const rect = canvas.getBoundingClientRect();
      const mx = event.clientX - rect.left, my = event.clientY - rect.top;
      const delta = event.deltaY * (event.deltaMode === 1 ? 16 : event.deltaMode === 2 ? 400 : 1);
      const f = Math.exp(-delta * 0.0015);
      view.scale *= f;
      view.ox = mx - (mx - view.ox) * f;
      view.oy = my - (my - view.oy) * f;
      view.moved = true;
      ui.requestViewDraw();
    }, { passive: false });

    view.width = Math.max(1, canvas.clientWidth);
    view.height = Math.max(1, canvas.clientHeight);
    fit();
    return { draw, resetCamera: resetView, resetLabel: 'reset view', hint: 'drag: pan · wheel: zoom · click: select a body · image frame: x right, y down', bodyAt };
  }

  // ---------------------------------------------------------------- page

  function showWarnings(warnings) {
    const banner = byId('warning-banner');
    if (!banner || warnings.length === 0) return;
    banner.textContent = '';
    warnings.forEach((w) => banner.appendChild(makeElement('div', 'warning', '⚠ ' + w)));
    banner.hidden = false;
  }

  function showViewMessage(message) {
    const element = byId('view-message');
    element.textContent = message;
    element.hidden = false;
  }

  function formatTime(model, t) {
    if (model.dt && model.dt > 0) {
      const decimals = clamp(Math.ceil(-Math.log10(model.dt) - 1e-9), 0, 6);
      return t.toFixed(decimals);
    }
    return formatNumber(t, 5);
  }

  function start() {
    const body = document.body;
    let model;
    const timings = [['script start', performance.now()]];
    try {
      const raw = readEmbeddedData();
      timings.push(['JSON.parse', performance.now()]);
      model = buildModel(raw);
      timings.push(['check data', performance.now()]);
    } catch (e) {
      const message = e && e.isDataError ? 'bad data: ' + e.message : 'viewer failed while reading the data: ' + (e && e.message);
      reportError(message);
      showViewMessage('Nothing to show: ' + message);
      body.dataset.status = 'error';
      return;
    }
    showWarnings(model.warnings);

    const n = model.frames.length;
    // Selected at first: the first body that moves (2D images often start with a pinned one).
    const firstMoving = model.dim === 2 ? Math.max(0, model.pinned.indexOf(false)) : 0;
    const state = { frame: 0, playing: false, speed: 1, showContacts: true, showTangentFrame: false, impulseFactor: 1, opacity: 1, selected: firstMoving, playWall: 0, playTime: 0 };
    const slider = byId('time-slider');
    const playButton = byId('play-pause');
    const readout = byId('readout');
    const statusLine = byId('status-line');
    const bodySelect = byId('body-select');
    const bodyState = byId('body-state');
    let view = null;
    let plots = null;
    let viewDirty = true, cursorDirty = true, drawPending = false;

    byId('scene-title').textContent = 'rigidref view: ' + (model.scene || '(unnamed scene)');
    const info = [model.dim + 'D', model.nb + (model.nb === 1 ? ' body' : ' bodies'), n + (n === 1 ? ' frame' : ' frames')];
    if (model.dt) info.push('dt = ' + model.dt + ' ' + model.timeUnit);
    if (model.dim === 2) info.push(model.blockCount + ' blocks');
    if (model.source) info.push(model.source);
    byId('scene-info').textContent = info.join(' · ');
    byId('scene-info').title = escapeForTitle(byId('scene-info').textContent);

    function requestDraw() {
      if (drawPending) return;
      drawPending = true;
      requestAnimationFrame(onAnimationFrame);
    }
    function requestViewDraw() { viewDirty = true; requestDraw(); }

    function onAnimationFrame(now) {
      drawPending = false;
      if (state.playing) advancePlayback(now);
      if (viewDirty && view) { viewDirty = false; view.draw(); }
      if (cursorDirty && plots) { cursorDirty = false; plots.drawCursors(state.frame); }
      if (state.playing) requestDraw();
    }

    // Playback follows the frames' t values: simulated time = time at play + wall time x speed.
    function advancePlayback(now) {
      const t = state.playTime + Math.max(0, now - state.playWall) / 1000 * state.speed;
      const k = frameAtOrBefore(model.times, t);
      if (k >= n - 1) { setFrame(n - 1); pause(); return; }
      if (k !== state.frame) setFrame(k);
    }

    function play() {
      if (n < 2) return;
      if (state.frame >= n - 1) setFrame(0);
      state.playing = true;
      state.playWall = performance.now();
      state.playTime = model.times[state.frame];
      updatePlayButton();
      requestDraw();
    }
    function pause() {
      state.playing = false;
      updatePlayButton();
    }
    function updatePlayButton() {
      playButton.textContent = state.playing ? '❚❚ pause' : '▶ play';
    }

    function setFrame(k) {
      k = clamp(Math.round(Number(k)) || 0, 0, n - 1);
      state.frame = k;
      slider.value = String(k);
      const f = model.frames[k];
      const step = f.step === undefined ? k : f.step;
      readout.textContent = 't = ' + formatTime(model, f.t) + ' ' + model.timeUnit + ', step ' + step + ', frame ' + k + '/' + (n - 1);
      updateStatusLine();
      updateBodyPanel();
      if (plots) plots.updateLegendValues(k);
      body.dataset.frame = String(k);
      viewDirty = true;
      cursorDirty = true;
      requestDraw();
    }
    function seek(k) { pause(); setFrame(k); }
    function seekTime(t) { pause(); setFrame(nearestFrame(model.times, t)); }

    function updateStatusLine() {
      const f = model.frames[state.frame];
      const parts = [];
      if (f.contacts === null) parts.push('contacts not recorded for this frame');
      else parts.push(f.contacts.length + (f.contacts.length === 1 ? ' contact' : ' contacts') + (state.showContacts ? '' : ' (hidden)'));
      if (state.showContacts && f.contacts && f.contacts.length) {
        const perUnit = model.autoImpulseScale * state.impulseFactor;
        parts.push('impulse arrows: 1 ' + model.impulseUnit + ' = ' + formatNumber(perUnit, 3) + ' ' + model.lengthUnit);
      }
      if (!view && model.dim === 3) parts.push('3D view unavailable (no WebGL)');
      statusLine.textContent = parts.join(' · ');
    }

    function stateRow(key, value, unit) {
      const row = makeElement('div', 'state-row');
      row.appendChild(makeElement('span', 'state-key', key));
      row.appendChild(makeElement('span', 'state-value', value));
      if (unit) row.appendChild(makeElement('span', 'state-unit', unit));
      return row;
    }

    function updateBodyPanel() {
      const i = state.selected;
      const f = model.frames[state.frame];
      const p = f.pose, o = i * model.stride;
      const v = f.vel, ov = i * model.velStride;
      const left = makeElement('div', 'state-column'), right = makeElement('div', 'state-column');
      const L = model.lengthUnit;
      const mass = model.masses[i];
      let massText = mass === null ? '–' : formatNumber(mass, 5);
      if (model.dim === 2 && model.pinned[i]) massText += ' (pinned)';
      if (model.dim === 3) {
        left.append(stateRow('x', formatVector([p[o], p[o + 1], p[o + 2]], 5), L),
          stateRow('v', v ? formatVector([v[ov], v[ov + 1], v[ov + 2]], 5) : '–', model.velocityUnit),
          stateRow('ω', v ? formatVector([v[ov + 3], v[ov + 4], v[ov + 5]], 5) : '–', model.omegaUnit));
        right.append(stateRow('R', formatVector([p[o + 3], p[o + 4], p[o + 5]], 5), ''),
          stateRow('', formatVector([p[o + 6], p[o + 7], p[o + 8]], 5), ''),
          stateRow('', formatVector([p[o + 9], p[o + 10], p[o + 11]], 5), ''),
          stateRow('mass', massText, model.massUnit));
      } else {
        left.append(stateRow('x', formatVector([p[o], p[o + 1]], 5), L),
          stateRow('v', v ? formatVector([v[ov], v[ov + 1]], 5) : '–', model.velocityUnit));
        right.append(stateRow('θ', formatNumber(p[o + 2], 5), 'rad (' + formatNumber(p[o + 2] * 180 / Math.PI, 4) + '°)'),
          stateRow('ω', v ? formatNumber(v[ov + 2], 5) : '–', model.omegaUnit),
          stateRow('mass', massText, model.massUnit));
      }
      bodyState.replaceChildren(left, right);
    }

    function selectBody(i) {
      state.selected = clamp(i, 0, model.nb - 1);
      bodySelect.value = String(state.selected);
      updateBodyPanel();
      requestViewDraw();
    }

    // body select
    const fragment = document.createDocumentFragment();
    model.names.forEach((name, i) => {
      const option = document.createElement('option');
      option.value = String(i);
      option.textContent = i + ': ' + name + (model.dim === 2 && model.pinned[i] ? ' (pinned)' : '');
      fragment.appendChild(option);
    });
    bodySelect.appendChild(fragment);
    bodySelect.value = String(state.selected);
    bodySelect.addEventListener('change', () => selectBody(Number(bodySelect.value)));

    // controls
    slider.max = String(n - 1);
    slider.addEventListener('input', () => seek(Number(slider.value)));
    playButton.addEventListener('click', () => (state.playing ? pause() : play()));
    byId('step-back').addEventListener('click', () => seek(state.frame - 1));
    byId('step-forward').addEventListener('click', () => seek(state.frame + 1));
    const speed = byId('speed');
    speed.addEventListener('change', () => {
      state.speed = Number(speed.value) || 1;
      if (state.playing) { state.playWall = performance.now(); state.playTime = model.times[state.frame]; }
    });
    const contactsBox = byId('show-contacts');
    contactsBox.addEventListener('change', () => { state.showContacts = contactsBox.checked; updateStatusLine(); requestViewDraw(); });
    const tangentBox = byId('show-tangent-frame');
    tangentBox.addEventListener('change', () => { state.showTangentFrame = tangentBox.checked; requestViewDraw(); });
    if (model.dim !== 3) byId('tangent-frame-label').hidden = true;
    const impulseSlider = byId('impulse-scale');
    const impulseLabel = byId('impulse-scale-label');
    function updateImpulseScale() {
      state.impulseFactor = Math.pow(10, Number(impulseSlider.value));
      impulseLabel.textContent = '×' + formatNumber(state.impulseFactor, 2) + (Number(impulseSlider.value) === 0 ? ' (auto)' : '');
      updateStatusLine();
      requestViewDraw();
    }
    impulseSlider.addEventListener('input', updateImpulseScale);
    const opacity = byId('opacity');
    if (model.dim !== 2) byId('opacity-label').hidden = true;
    opacity.addEventListener('input', () => { state.opacity = Number(opacity.value); requestViewDraw(); });

    // Keyboard: space plays/pauses, arrows step; native keys of focused controls are left alone.
    document.addEventListener('keydown', (event) => {
      if (event.ctrlKey || event.metaKey || event.altKey) return;
      const target = event.target;
      const tag = target && target.tagName;
      const isRange = tag === 'INPUT' && target.type === 'range';
      if (tag === 'SELECT' || tag === 'TEXTAREA' || tag === 'BUTTON' || (tag === 'INPUT' && !isRange)) return;
      if (event.key === ' ' || event.code === 'Space') {
        event.preventDefault();
        if (state.playing) pause(); else play();
      } else if (!isRange && event.key === 'ArrowLeft') {
        event.preventDefault(); seek(state.frame - 1);
      } else if (!isRange && event.key === 'ArrowRight') {
        event.preventDefault(); seek(state.frame + 1);
      }
    });

    const ui = { state, requestViewDraw, selectBody, showViewMessage };
    const canvas = byId('view-canvas');
    view = model.dim === 3 ? createView3D(canvas, model, ui) : createView2D(canvas, model, ui);
    const resetButton = byId('reset-camera');
    if (view) {
      resetButton.textContent = view.resetLabel;
      resetButton.addEventListener('click', () => view.resetCamera());
      byId('view-hint').textContent = view.hint;
    } else {
      resetButton.disabled = true;
      canvas.hidden = true;
      showViewMessage('WebGL is not available in this browser, so the 3D view cannot be drawn. The plots, the controls and the body panel below still work.');
    }

    plots = createPlots(byId('plots'), model, seekTime);
    updateImpulseScale();
    timings.push(['build page', performance.now()]);

    // Test hook and deep link: #frame=K or #t=SECONDS, paused. Optional extra keys, joined with
    // '&': body=K (selected body), contacts=0|1, tangent=0|1, opacity=X (2D), impulse=X (factor).
    function applyHash() {
      const hash = location.hash.replace(/^#/, '');
      const params = new URLSearchParams(hash);
      if (params.has('body')) selectBody(Number(params.get('body')) || 0);
      if (params.has('contacts')) { contactsBox.checked = params.get('contacts') !== '0'; state.showContacts = contactsBox.checked; }
      if (params.has('tangent')) { tangentBox.checked = params.get('tangent') !== '0'; state.showTangentFrame = tangentBox.checked; }
      if (params.has('opacity')) { opacity.value = params.get('opacity'); state.opacity = Number(opacity.value); }
      if (params.has('impulse') && Number(params.get('impulse')) > 0) { impulseSlider.value = String(Math.log10(Number(params.get('impulse')))); updateImpulseScale(); }
      if (params.has('frame')) seek(Number(params.get('frame')));
      else if (params.has('t')) seekTime(Number(params.get('t')));
      else return false;
      return true;
    }
    window.addEventListener('hashchange', applyHash);
    if (!applyHash()) setFrame(0);

    // Redraw on resize (the view and the plots' widths follow the layout).
    let resizePending = false;
    const observer = new ResizeObserver(() => {
      if (resizePending) return;
      resizePending = true;
      requestAnimationFrame(() => {
        resizePending = false;
        plots.redrawAll();
        cursorDirty = true;
        viewDirty = true;
        requestDraw();
      });
    });
    observer.observe(byId('view'));
    observer.observe(byId('plots'));

    window.rigidrefView = {
      seek,
      frameCount: () => n,
      play,
      pause,
      currentFrame: () => state.frame,
      isPlaying: () => state.playing,
      // Runs what the next animation frame would (playback step, pending redraws) right now:
      // headless Chromium's --dump-dom mode never runs requestAnimationFrame callbacks.
      drawNow() { onAnimationFrame(performance.now()); },
      // Draws `count` frames spread over the run synchronously; returns the mean ms per view draw.
      benchmark(count) {
        if (!view) return null;
        count = count || 20;
        const keep = state.frame, t0 = performance.now();
        for (let k = 0; k < count; k++) { state.frame = Math.round(k * (n - 1) / Math.max(1, count - 1)); view.draw(); }
        const ms = (performance.now() - t0) / count;
        setFrame(keep);
        return ms;
      },
    };

    // First frame synchronously, so "ready" means drawn.
    if (view) { view.draw(); viewDirty = false; }
    timings.push(['first view draw', performance.now()]);
    plots.redrawAll();
    plots.drawCursors(state.frame);
    cursorDirty = false;
    timings.push(['plots draw', performance.now()]);
    // Where the time to the first frame went (ms), for measuring big files.
    body.dataset.timings = timings.map((t, i) => t[0] + ' ' + (i === 0 ? t[1] : t[1] - timings[i - 1][1]).toFixed(0)).join(', ');
    const rect = byId('view').getBoundingClientRect();
    body.dataset.viewRect = [rect.left, rect.top, rect.width, rect.height].map(Math.round).join(',');
    body.dataset.frame = String(state.frame);
    body.dataset.readyMs = performance.now().toFixed(1);
    // Measuring hook: #bench=N draws N frames spread over the run and records the mean ms per
    // view draw (how interactive a big run stays; docs/viewing.md).
    const benchCount = Number(new URLSearchParams(location.hash.replace(/^#/, '')).get('bench'));
    if (benchCount > 0 && view) body.dataset.drawMs = window.rigidrefView.benchmark(benchCount).toFixed(2);
    body.dataset.status = view || model.dim !== 3 ? 'ready' : 'no-webgl';
  }

  try {
    start();
  } catch (e) {
    reportError('viewer failed: ' + (e && e.message ? e.message : String(e)));
    if (!document.body.dataset.status || document.body.dataset.status === 'ready') document.body.dataset.status = 'error';
  }
})();

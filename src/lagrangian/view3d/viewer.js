/* The viewer of lagrangian's 3-D view: draws a scene document (format lagrangian.view/1) with three.js.
 *
 * Everything the page shows comes from the document: carriers and their poses per frame (position +
 * quaternion, float32, base64), parts fixed to carriers, tracked points, links, triads, arcs, arrows.
 * Between two frames, positions are interpolated linearly and orientations by slerp.  Names and labels
 * are written with textContent, never as HTML.  Nothing is fetched: the page works offline.
 *
 * For tests and scripts, each viewer is in window.lagrangianViews (the last one is window.lagrangianView):
 * setTime(t), time(), play(), pause(), playing(), cameraMatrix(), project([x, y, z]), render(),
 * benchmark(seconds) and frameCount.
 */
var LagrangianView = (function () {
  "use strict";

  function bytes(text) {
    var raw = atob(text), out = new Uint8Array(raw.length);
    for (var i = 0; i < raw.length; i++) out[i] = raw.charCodeAt(i);
    return out.buffer;
  }
  function f32(text) { return new Float32Array(bytes(text)); }
  function f64(text) { return new Float64Array(bytes(text)); }
  function el(tag, cls, text) {
    var e = document.createElement(tag);
    if (cls) e.className = cls;
    if (text !== undefined) e.textContent = text;
    return e;
  }
  function darker(hex, k) {
    var c = new THREE.Color(hex);
    return c.multiplyScalar(k);
  }

  var STYLE = [
    ".lgv{position:relative;width:100%;height:100%;min-height:320px;font:13px system-ui,sans-serif;",
    "background:#fff;color:#222;overflow:hidden;display:flex;flex-direction:column}",
    ".lgv-stage{position:relative;flex:1 1 auto;min-height:200px}",
    ".lgv-stage canvas{display:block;width:100%;height:100%;outline:none}",
    ".lgv-labels{position:absolute;left:0;top:0;right:0;bottom:0;pointer-events:none;overflow:hidden}",
    ".lgv-label{position:absolute;left:0;top:0;white-space:nowrap;font-size:12px;will-change:transform;",
    "color:#222;text-shadow:0 0 2px #fff,0 0 2px #fff}",
    ".lgv-label.lgv-axis{color:#555;font-style:italic}.lgv-label.lgv-arc{color:#a0522d;font-style:italic}",
    ".lgv-label.lgv-body{color:#444;font-weight:600}",
    ".lgv-bar{display:flex;flex-wrap:wrap;align-items:center;gap:6px 10px;padding:6px 8px;border-top:1px solid #ddd;",
    "background:#f7f7f7}",
    ".lgv-bar input[type=range].lgv-slider{flex:1 1 200px;min-width:120px}",
    ".lgv-bar button{min-width:64px}",
    ".lgv-time{font-variant-numeric:tabular-nums;min-width:92px}",
    ".lgv-bar label{white-space:nowrap}",
    ".lgv-bar details{position:relative}",
    ".lgv-bar details>div{position:absolute;bottom:1.8em;left:0;background:#fff;border:1px solid #ccc;",
    "padding:6px;z-index:2;max-height:240px;overflow:auto;min-width:160px}",
    ".lgv-title{position:absolute;left:8px;top:6px;font-weight:600;pointer-events:none;",
    "text-shadow:0 0 2px #fff}"
  ].join("");

  var views = [];

  function mount(container, doc) {
    if (!doc || doc.format !== "lagrangian.view/1") throw new Error("not a lagrangian.view/1 scene");
    if (!document.getElementById("lgv-style")) {
      var style = el("style");
      style.id = "lgv-style";
      style.textContent = STYLE;
      document.head.appendChild(style);
    }
    container.classList.add("lgv");
    var stage = el("div", "lgv-stage");
    var labelsLayer = el("div", "lgv-labels");
    var bar = el("div", "lgv-bar");
    container.appendChild(stage);
    container.appendChild(bar);
    stage.appendChild(el("div", "lgv-title", doc.title));

    var T = f64(doc.t), F = doc.frames, t0 = T[0], t1 = T[F - 1];
    var K = doc.carriers.length, P = doc.tracks.length;
    var runs = doc.runs.map(function (r) {
      return {label: r.label, poses: f32(r.poses), points: f32(r.points), offset: r.offset, ghost: r.ghost};
    });
    var up = new THREE.Vector3().fromArray(doc.up);
    var centre = new THREE.Vector3().fromArray(doc.centre);
    var L = doc.size;

    // -- renderer, camera, lights ---------------------------------------------------------------------------
    // Multisampling on a software renderer (SwiftShader, llvmpipe: no GPU) costs more than the rest of a frame.
    var probe = document.createElement("canvas").getContext("webgl2") || document.createElement("canvas").getContext("webgl");
    var info = probe && probe.getExtension("WEBGL_debug_renderer_info");
    var software = !!(info && /SwiftShader|llvmpipe|softpipe|Software/i.test(probe.getParameter(info.UNMASKED_RENDERER_WEBGL)));
    if (probe && probe.getExtension("WEBGL_lose_context")) probe.getExtension("WEBGL_lose_context").loseContext();
    // An opaque canvas (alpha: false) spares the compositor a blend of every pixel.
    var renderer = new THREE.WebGLRenderer({antialias: !software, alpha: false, stencil: false});
    renderer.setPixelRatio(1);
    renderer.setClearColor(0xffffff, 1);
    stage.appendChild(renderer.domElement);
    stage.appendChild(labelsLayer);
    var scene = new THREE.Scene();
    var camera = new THREE.PerspectiveCamera(35, 1, doc.radius / 100, doc.radius * 100);
    camera.up.copy(up);
    var dist = doc.radius / Math.tan(THREE.MathUtils.degToRad(35 / 2)) * 1.1;
    camera.position.copy(centre).addScaledVector(new THREE.Vector3().fromArray(doc.view_direction), dist);
    camera.lookAt(centre);
    scene.add(new THREE.AmbientLight(0xffffff, 0.55));
    var sun = new THREE.DirectionalLight(0xffffff, 1.6);
    sun.position.set(0.3, 0.4, 1);
    camera.add(sun);
    scene.add(camera);
    var controls = new OrbitControls(camera, renderer.domElement);
    controls.target.copy(centre);
    controls.update();

    // -- parts on carriers, one set per run ---------------------------------------------------------------
    var materials = {};
    function material(color, opacity, flat) {
      var key = color + "|" + opacity + "|" + (flat ? 1 : 0);
      if (!materials[key]) {
        materials[key] = new THREE.MeshLambertMaterial({color: new THREE.Color(color), transparent: opacity < 1,
                                                        opacity: opacity, flatShading: !!flat,
                                                        depthWrite: opacity >= 1});
      }
      return materials[key];
    }
    // Shapes of one kind share a unit geometry, drawn in one call per kind and opacity (an InstancedMesh whose
    // instances are the parts, each placed by its carrier's pose × its own place × its size): a chain of thirty
    // rods and thirty balls is two draw calls, which software renderers need.
    var small = doc.parts.length > 24;
    var UNIT = {};
    function unit(kind, joint) {
      var round = joint ? 12 : (small ? 20 : 32), key = kind + (joint ? "/joint" : "");
      if (!UNIT[key]) {
        if (kind === "sphere") UNIT[key] = new THREE.SphereGeometry(1, round, Math.max(8, round / 2));
        else if (kind === "box") UNIT[key] = new THREE.BoxGeometry(1, 1, 1);
        else if (kind === "cone") UNIT[key] = new THREE.ConeGeometry(1, 1, 24).rotateX(Math.PI / 2);
        else UNIT[key] = new THREE.CylinderGeometry(1, 1, 1, kind === "rod" || joint ? 12 : round + 8)
          .rotateX(Math.PI / 2);  // cylinder, disk, rod: along z
      }
      return UNIT[key];
    }
    function meshGeometry(part) {
      var g = new THREE.BufferGeometry();
      g.setAttribute("position", new THREE.BufferAttribute(f32(part.mesh.vertices), 3));
      var idx = part.mesh.index === "uint16" ? new Uint16Array(bytes(part.mesh.triangles))
                                             : new Uint32Array(bytes(part.mesh.triangles));
      g.setIndex(new THREE.BufferAttribute(idx, 1));
      g.computeVertexNormals();
      return g;
    }
    var meshGeometries = doc.parts.map(function (part) { return part.kind === "mesh" ? meshGeometry(part) : null; });
    var batches = [];  // {mesh: InstancedMesh, run, items: [{carrier, local: Matrix4}]}
    function buildRun(run, r) {
      var opacity = run.ghost ? 0.28 : 1;
      var groups = [];
      for (var c = 0; c < K; c++) {
        var group = new THREE.Group();
        group.matrixAutoUpdate = false;
        scene.add(group);
        groups.push(group);
      }
      var pending = {};
      function add(geometry, o, carrier, local, colour) {
        var key = geometry.uuid + "|" + o;
        if (!pending[key]) pending[key] = {geometry: geometry, opacity: o, items: []};
        pending[key].items.push({carrier: carrier, local: local, color: new THREE.Color(colour)});
      }
      doc.parts.forEach(function (part, i) {
        var o = Math.min(opacity, part.opacity), m, s = part.size;
        var place = new THREE.Matrix4().compose(new THREE.Vector3().fromArray(part.position),
                                                new THREE.Quaternion().fromArray(part.rotation), new THREE.Vector3(1, 1, 1));
        if (part.kind === "mesh") {
          if (part.mesh.groups.length > 1) {
            var mats = part.mesh.groups.map(function (gr) { return material(gr[2] || part.color, o, true); });
            meshGeometries[i].clearGroups();
            part.mesh.groups.forEach(function (gr, j) { meshGeometries[i].addGroup(3 * gr[0], 3 * gr[1], j); });
            m = new THREE.Mesh(meshGeometries[i], mats);
          } else {
            var colour = part.mesh.groups.length === 1 && part.mesh.groups[0][2] ? part.mesh.groups[0][2] : part.color;
            m = new THREE.Mesh(meshGeometries[i], material(colour, o, true));
          }
          m.position.fromArray(part.position);
          m.quaternion.fromArray(part.rotation);
          groups[part.carrier].add(m);
          return;
        }
        var joint = part.source === "hinge" || part.source === "ball";
        var size = part.kind === "sphere" ? [s[0], s[0], s[0]] : part.kind === "box" ? s : [s[0], s[0], Math.max(s[1], 1e-9)];
        add(unit(part.kind, joint), o, part.carrier,
            place.clone().multiply(new THREE.Matrix4().makeScale(size[0], size[1], size[2])), part.color);
        if (part.spoke && (part.kind === "disk" || part.kind === "cylinder")) {
          var rr = s[0], h = Math.max(s[1], rr / 12);
          add(unit("box"), o, part.carrier, place.clone().multiply(new THREE.Matrix4().compose(
            new THREE.Vector3(0.45 * rr, 0, 0), new THREE.Quaternion(), new THREE.Vector3(0.9 * rr, 0.14 * rr, 1.04 * h))),
            "#" + darker(part.color, 0.45).getHexString());
        }
      });
      Object.keys(pending).forEach(function (key) {
        var b = pending[key];
        var mesh = new THREE.InstancedMesh(b.geometry, material("#ffffff", b.opacity), b.items.length);
        b.items.forEach(function (item, j) { mesh.setColorAt(j, item.color); });
        mesh.instanceColor.needsUpdate = true;
        mesh.frustumCulled = false;
        scene.add(mesh);
        batches.push({mesh: mesh, run: r, items: b.items});
      });
      return groups;
    }
    var runGroups = runs.map(buildRun);

    // -- links, fixed points, ground ----------------------------------------------------------------------
    var unitRod = new THREE.CylinderGeometry(1, 1, 1, 12).rotateX(Math.PI / 2);
    var links = [];
    runs.forEach(function (run, r) {
      doc.links.forEach(function (link) {
        var o = run.ghost ? 0.28 : 1, obj;
        if (link.kind === "spring") {
          var geo = new THREE.BufferGeometry();
          geo.setAttribute("position", new THREE.BufferAttribute(new Float32Array(3 * 161), 3));
          obj = new THREE.Line(geo, new THREE.LineBasicMaterial({color: new THREE.Color(link.color),
                                                                  transparent: o < 1, opacity: o}));
        } else if (link.kind === "damper") {
          obj = new THREE.Group();
          obj.add(new THREE.Mesh(unitRod, material(link.color, o)));
          obj.add(new THREE.Mesh(unitRod, material("#999999", o)));
        } else {
          obj = new THREE.Mesh(unitRod, material(link.color, o));
        }
        obj.frustumCulled = false;
        scene.add(obj);
        links.push({link: link, run: r, obj: obj});
      });
    });
    var fixedMarkers = [];
    doc.tracks.forEach(function (tr, i) {
      if (!tr.fixed) return;
      var cone = new THREE.Mesh(new THREE.ConeGeometry(0.045 * L, 0.08 * L, 24), material("#333333", 1));
      cone.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), up);
      fixedMarkers.push({track: i, obj: cone});
      scene.add(cone);
    });
    var lowest = Infinity, tmp = new THREE.Vector3();
    for (var f = 0; f < F; f++) for (var p = 0; p < P; p++) {
      tmp.fromArray(runs[0].points, 3 * (f * P + p));
      lowest = Math.min(lowest, tmp.dot(up));
    }
    var floorAt = lowest - 0.1 * L;
    var grid = new THREE.GridHelper(3 * doc.radius, 12, 0xcfcfcf, 0xe9e9e9);
    grid.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), up);
    grid.position.copy(centre).addScaledVector(up, floorAt - centre.dot(up));
    scene.add(grid);

    // -- triads, arcs, traces, arrows -------------------------------------------------------------------------
    var AXIS_COLORS = [0xd62728, 0x2ca02c, 0x1f77b4];
    var triads = doc.triads.map(function (tr) {
      var group = new THREE.Group();
      var basis = [new THREE.Vector3(1, 0, 0), new THREE.Vector3(0, 1, 0), new THREE.Vector3(0, 0, 1)];
      tr.axes.forEach(function (name, k) {
        if (!name) return;
        var arrow = new THREE.ArrowHelper(basis[k], new THREE.Vector3(), tr.length, AXIS_COLORS[k],
                                          0.12 * tr.length, 0.06 * tr.length);
        group.add(arrow);
      });
      group.position.fromArray(tr.position);
      runGroups[0][tr.carrier].add(group);
      return group;
    });
    var arcs = doc.arcs.map(function (a) {
      var geo = new THREE.BufferGeometry().setFromPoints(a.points.map(function (p) {
        return new THREE.Vector3().fromArray(p); }));
      var line = new THREE.Line(geo, new THREE.LineBasicMaterial({color: 0xa0522d}));
      scene.add(line);
      return line;
    });
    var traces = [];
    runs.forEach(function (run, r) {
      if (run.ghost) return;
      doc.traces.forEach(function (i) {
        var geo = new THREE.BufferGeometry();
        var pos = new Float32Array(3 * F);
        for (var f = 0; f < F; f++) for (var k = 0; k < 3; k++)
          pos[3 * f + k] = run.points[3 * (f * P + i) + k] + run.offset[k];
        geo.setAttribute("position", new THREE.BufferAttribute(pos, 3));
        var owner = doc.tracks[i].name.replace(/^tip:/, "");
        var colour = (doc.parts.find(function (p) { return p.owner === owner; }) || {color: "#888888"}).color;
        var line = new THREE.Line(geo, new THREE.LineBasicMaterial({color: darker(colour, 0.75)}));
        line.frustumCulled = false;
        scene.add(line);
        traces.push({track: i, run: r, line: line});
      });
    });
    var arrowScale = 1;
    var arrows = doc.arrows.map(function (a) {
      var helper = new THREE.ArrowHelper(new THREE.Vector3(0, 0, 1), new THREE.Vector3(), 1, new THREE.Color(a.color));
      helper.visible = false;
      scene.add(helper);
      return {doc: a, values: f32(a.values), helper: helper, shown: a.shown};
    });

    // -- labels -----------------------------------------------------------------------------------------------
    var labels = [];
    function label(text, cls, where) {
      if (!text) return;
      var span = el("span", "lgv-label " + (cls || ""), text);
      labelsLayer.appendChild(span);
      labels.push({span: span, where: where, cls: cls || ""});
    }
    doc.tracks.forEach(function (tr, i) {
      if (tr.kind !== "tip") label(tr.label, "lgv-point", {track: i});
    });
    doc.carriers.forEach(function (c, k) {
      if (c.kind === "body" || c.kind === "particle") {
        var hasTrack = doc.tracks.some(function (tr) { return tr.name === c.name && tr.kind === "particle"; });
        if (!hasTrack) label("(" + c.label + ")", "lgv-body", {carrier: k, shift: 0.12 * L});
      }
    });
    doc.triads.forEach(function (tr, j) {
      var origin = new THREE.Vector3().fromArray(tr.position);
      if (tr.axes.every(function (n) { return n.length === 1; }))
        label(tr.frame, "lgv-axis", {carrier: tr.carrier, local: origin.clone(), frameLabel: true});
      tr.axes.forEach(function (name, k) {
        var local = origin.clone();
        local.setComponent(k, local.getComponent(k) + tr.length * 1.08);
        label(name, "lgv-axis", {carrier: tr.carrier, local: local});
      });
    });
    doc.arcs.forEach(function (a, j) { label(a.label, "lgv-arc", {fixed: new THREE.Vector3().fromArray(a.at), arc: j}); });
    arrows.forEach(function (a, j) { label(a.doc.label, "lgv-vector", {arrow: j}); });

    // -- state ------------------------------------------------------------------------------------------------
    var bodies = doc.carriers.filter(function (c) { return c.kind === "body" || c.kind === "particle"; }).length;
    // A large model starts without its labels and triads (they would hide it); each can be switched on.
    var state = {time: t0, playing: false, speed: 1, frames: doc.triads.length <= 5, labels: bodies <= 8,
                 angles: true, traces: true, ghosts: true, last: null, frameCount: 0};
    var traceShown = doc.traces.map(function () { return true; });
    var qa = new THREE.Quaternion(), pa = new THREE.Vector3(), m4 = new THREE.Matrix4(), one = new THREE.Vector3(1, 1, 1);
    var quat = new Float32Array(4), placed = new THREE.Matrix4();
    var index = 0, alpha = 0;

    function locate(t) {
      if (F === 1) { index = 0; alpha = 0; return; }
      t = Math.min(Math.max(t, t0), t1);
      var lo = 0, hi = F - 1;
      while (hi - lo > 1) { var mid = (lo + hi) >> 1; if (T[mid] <= t) lo = mid; else hi = mid; }
      index = lo;
      alpha = T[hi] > T[lo] ? (t - T[lo]) / (T[hi] - T[lo]) : 0;
    }
    function trackAt(run, i, out) {
      var a = 3 * (index * P + i), b = index + 1 < F ? 3 * ((index + 1) * P + i) : a, pts = run.points;
      out.set(pts[a] + alpha * (pts[b] - pts[a]), pts[a + 1] + alpha * (pts[b + 1] - pts[a + 1]),
              pts[a + 2] + alpha * (pts[b + 2] - pts[a + 2]));
      out.x += run.offset[0]; out.y += run.offset[1]; out.z += run.offset[2];
      return out;
    }
    function poseAt(run, k) {
      var a = 7 * (index * K + k), b = index + 1 < F ? 7 * ((index + 1) * K + k) : a, ps = run.poses;
      pa.set(ps[a] + alpha * (ps[b] - ps[a]) + run.offset[0], ps[a + 1] + alpha * (ps[b + 1] - ps[a + 1]) + run.offset[1],
             ps[a + 2] + alpha * (ps[b + 2] - ps[a + 2]) + run.offset[2]);
      THREE.Quaternion.slerpFlat(quat, 0, ps, a + 3, ps, b + 3, alpha);
      qa.set(quat[0], quat[1], quat[2], quat[3]);
    }
    var va = new THREE.Vector3(), vb = new THREE.Vector3(), vd = new THREE.Vector3(), yAxis = new THREE.Vector3(0, 0, 1);
    function placeBetween(obj, a, b, radius, from, share) {
      vd.subVectors(b, a);
      var len = vd.length();
      if (len < 1e-12) { obj.visible = false; return; }
      obj.visible = true;
      obj.quaternion.setFromUnitVectors(yAxis, vd.clone().divideScalar(len));
      var start = from === undefined ? 0 : from, part = share === undefined ? 1 : share;
      obj.position.copy(a).addScaledVector(vd, start + part / 2);
      obj.scale.set(radius, radius, len * part);
    }
    function update() {
      locate(state.time);
      runs.forEach(function (run, r) {
        var show = !run.ghost || state.ghosts;
        for (var k = 0; k < K; k++) {
          var g = runGroups[r][k];
          g.visible = show;
          poseAt(run, k);
          g.matrix.compose(pa, qa, one);
          g.matrixWorldNeedsUpdate = true;
        }
      });
      batches.forEach(function (b) {
        var show = !runs[b.run].ghost || state.ghosts;
        b.mesh.visible = show;
        if (!show) return;
        var groups = runGroups[b.run];
        b.items.forEach(function (item, j) {
          placed.multiplyMatrices(groups[item.carrier].matrix, item.local);
          b.mesh.setMatrixAt(j, placed);
        });
        b.mesh.instanceMatrix.needsUpdate = true;
      });
      links.forEach(function (l) {
        var run = runs[l.run];
        l.obj.visible = !run.ghost || state.ghosts;
        trackAt(run, l.link.a, va);
        trackAt(run, l.link.b, vb);
        if (l.link.kind === "spring") {
          var pos = l.obj.geometry.attributes.position, n = 160, coils = 10;
          vd.subVectors(vb, va);
          var u = new THREE.Vector3().crossVectors(vd, Math.abs(vd.x) < 0.9 * vd.length() ? new THREE.Vector3(1, 0, 0)
                                                                                          : new THREE.Vector3(0, 1, 0)).normalize();
          var w = new THREE.Vector3().crossVectors(vd, u).normalize();
          for (var s = 0; s <= n; s++) {
            var x = s / n, ring = (s < 8 || s > n - 8) ? 0 : l.link.radius, ang = 2 * Math.PI * coils * x;
            pos.setXYZ(s, va.x + x * vd.x + ring * (Math.cos(ang) * u.x + Math.sin(ang) * w.x),
                       va.y + x * vd.y + ring * (Math.cos(ang) * u.y + Math.sin(ang) * w.y),
                       va.z + x * vd.z + ring * (Math.cos(ang) * u.z + Math.sin(ang) * w.z));
          }
          pos.needsUpdate = true;
        } else if (l.link.kind === "damper") {
          placeBetween(l.obj.children[0], va, vb, l.link.radius, 0, 0.55);
          placeBetween(l.obj.children[1], va, vb, 0.35 * l.link.radius, 0.45, 0.55);
        } else {
          placeBetween(l.obj, va, vb, l.link.radius);
        }
      });
      fixedMarkers.forEach(function (m) {
        trackAt(runs[0], m.track, va);
        m.obj.position.copy(va).addScaledVector(up, -0.04 * L);
      });
      triads.forEach(function (g) { g.visible = state.frames; });
      var atStart = F === 1 || Math.abs(state.time - t0) <= 0.5 * (T[1] - T[0]);
      arcs.forEach(function (a) { a.visible = state.angles && atStart; });
      traces.forEach(function (tr, j) {
        tr.line.visible = state.traces && traceShown[j % doc.traces.length] && F > 1;
        tr.line.geometry.setDrawRange(0, index + 1);
      });
      arrows.forEach(function (a) {
        if (!a.shown) { a.helper.visible = false; return; }
        var v = a.values, i = 3 * index, j = index + 1 < F ? i + 3 : i;
        vd.set(v[i] + alpha * (v[j] - v[i]), v[i + 1] + alpha * (v[j + 1] - v[i + 1]), v[i + 2] + alpha * (v[j + 2] - v[i + 2]));
        var len = vd.length() * a.doc.scale * arrowScale;
        trackAt(runs[0], a.doc.track, va);
        a.helper.visible = len > 1e-9 * L;
        if (a.helper.visible) {
          a.helper.position.copy(va);
          a.helper.setDirection(vd.normalize());
          a.helper.setLength(len, Math.min(0.25 * len, 0.08 * L), Math.min(0.12 * len, 0.04 * L));
        }
        a.tip = va.clone().addScaledVector(vd, len);
      });
    }

    var size = {width: 1, height: 1};
    function resize() {
      var w = stage.clientWidth || 640, h = stage.clientHeight || 480;
      if (w === size.width && h === size.height) return;
      size.width = w; size.height = h;
      renderer.setSize(w, h, false);
      camera.aspect = w / h;
      camera.updateProjectionMatrix();
    }
    var proj = new THREE.Vector3();
    function place() {
      labelsLayer.style.display = state.labels ? "" : "none";
      if (!state.labels) return;
      labels.forEach(function (l) {
        var w = l.where, show = true;
        if (w.track !== undefined) trackAt(runs[0], w.track, proj);
        else if (w.carrier !== undefined) {
          poseAt(runs[0], w.carrier);
          proj.copy(w.local || new THREE.Vector3()).applyQuaternion(qa).add(pa);
          if (w.shift) proj.addScaledVector(up, w.shift);
          if (w.local) show = state.frames;
        } else if (w.fixed) {
          proj.copy(w.fixed);
          show = state.angles && (F === 1 || Math.abs(state.time - t0) <= 0.5 * (T[1] - T[0]));
        } else if (w.arrow !== undefined) {
          var a = arrows[w.arrow];
          show = a.shown && a.helper.visible && !!a.tip;
          if (show) proj.copy(a.tip);
        }
        proj.project(camera);
        if (!show || proj.z > 1 || proj.z < -1) { l.span.style.display = "none"; return; }
        if (l.span.style.display) l.span.style.display = "";
        var x = Math.round((proj.x + 1) / 2 * size.width) + 4, y = Math.round((1 - proj.y) / 2 * size.height) - 8;
        if (x !== l.x || y !== l.y) {  // moved: a transform, which needs no layout of the page
          l.span.style.transform = "translate(" + x + "px," + y + "px)";
          l.x = x; l.y = y;
        }
      });
    }
    var timeText, slider;
    function render() {
      resize();
      update();
      scene.updateMatrixWorld();
      renderer.render(scene, camera);
      place();
      state.frameCount++;
      if (timeText) timeText.textContent = "t = " + state.time.toFixed(3) + " s";
      if (slider && document.activeElement !== slider) slider.value = String(Math.round(1000 * (state.time - t0) / Math.max(t1 - t0, 1e-300)));
    }
    var pending = false;
    function requestRender() {
      if (pending || state.playing) return;
      pending = true;
      requestAnimationFrame(function () { pending = false; render(); });
    }
    function loop(now) {
      if (!state.playing) { state.last = null; return; }
      if (state.last !== null) {
        state.time += (now - state.last) / 1000 * state.speed;
        if (state.time > t1) state.time = t0 + (state.time - t1) % Math.max(t1 - t0, 1e-300);
      }
      state.last = now;
      render();
      requestAnimationFrame(loop);
    }
    controls.addEventListener("change", requestRender);

    // -- the bar -------------------------------------------------------------------------------------------------
    var playButton = el("button", "lgv-play", "▶ play");
    playButton.type = "button";
    function setPlaying(on) {
      if (F === 1) on = false;
      if (on === state.playing) return;
      state.playing = on;
      playButton.textContent = on ? "❚❚ pause" : "▶ play";
      if (on) requestAnimationFrame(loop); else requestRender();
    }
    playButton.addEventListener("click", function () { setPlaying(!state.playing); });
    slider = el("input", "lgv-slider");
    slider.type = "range"; slider.min = "0"; slider.max = "1000"; slider.value = "0";
    slider.setAttribute("aria-label", "time");
    slider.addEventListener("input", function () {
      state.time = t0 + (t1 - t0) * Number(slider.value) / 1000;
      requestRender();
    });
    timeText = el("span", "lgv-time", "t = " + t0.toFixed(3) + " s");
    var speed = el("select", "lgv-speed");
    [0.1, 0.25, 0.5, 1, 2, 4].forEach(function (s) {
      var o = el("option", "", "×" + s);
      o.value = String(s);
      if (s === 1) o.selected = true;
      speed.appendChild(o);
    });
    speed.setAttribute("aria-label", "playback speed");
    speed.addEventListener("change", function () { state.speed = Number(speed.value); });
    function toggle(text, key, enabled) {
      var box = el("input");
      box.type = "checkbox";
      box.checked = state[key];
      box.addEventListener("change", function () { state[key] = box.checked; requestRender(); });
      var lab = el("label");
      lab.appendChild(box);
      lab.appendChild(document.createTextNode(" " + text));
      if (enabled === false) lab.style.display = "none";
      return lab;
    }
    if (F > 1) { bar.appendChild(playButton); bar.appendChild(slider); bar.appendChild(timeText); bar.appendChild(speed); }
    bar.appendChild(toggle("frames", "frames", doc.triads.length > 0));
    bar.appendChild(toggle("labels", "labels"));
    bar.appendChild(toggle("angles", "angles", doc.arcs.length > 0));
    if (F > 1 && doc.traces.length) {
      var tr = el("details"), box = el("div");
      tr.appendChild(el("summary", "", "traces"));
      box.appendChild(toggle("show traces", "traces"));
      doc.traces.forEach(function (i, j) {
        var c = el("input");
        c.type = "checkbox"; c.checked = true;
        c.addEventListener("change", function () { traceShown[j] = c.checked; requestRender(); });
        var l = el("label");
        l.appendChild(c);
        var name = doc.tracks[i].kind === "tip" ? "tip of " + doc.tracks[i].name.slice(4) : doc.tracks[i].label;
        l.appendChild(document.createTextNode(" " + name));
        box.appendChild(el("br"));
        box.appendChild(l);
      });
      tr.appendChild(box);
      bar.appendChild(tr);
    }
    if (arrows.length) {
      var vec = el("details"), vbox = el("div");
      vec.appendChild(el("summary", "", "vectors"));
      arrows.forEach(function (a) {
        var c = el("input");
        c.type = "checkbox"; c.checked = a.shown;
        c.addEventListener("change", function () { a.shown = c.checked; requestRender(); });
        var l = el("label");
        l.appendChild(c);
        l.appendChild(document.createTextNode(" " + a.doc.label + " (" + (a.doc.scale).toPrecision(2) + " m per " +
                                              a.doc.unit + ")"));
        vbox.appendChild(l);
        vbox.appendChild(el("br"));
      });
      var scale = el("input");
      scale.type = "range"; scale.min = "-100"; scale.max = "100"; scale.value = "0";
      scale.setAttribute("aria-label", "vector scale");
      scale.addEventListener("input", function () { arrowScale = Math.pow(10, Number(scale.value) / 100); requestRender(); });
      var sl = el("label", "", "scale ");
      sl.appendChild(scale);
      vbox.appendChild(sl);
      vec.appendChild(vbox);
      bar.appendChild(vec);
    }
    if (runs.some(function (r) { return r.ghost; })) bar.appendChild(toggle("ensemble", "ghosts"));
    if (runs.length > 1) {
      bar.appendChild(el("span", "lgv-runs", runs.map(function (r) { return r.label; }).join(" · ")));
    }

    if (typeof ResizeObserver !== "undefined") new ResizeObserver(requestRender).observe(stage);
    render();

    var api = {
      container: container,
      setTime: function (t) { state.time = Math.min(Math.max(Number(t), t0), t1); render(); return state.time; },
      time: function () { return state.time; },
      play: function () { setPlaying(true); },
      pause: function () { setPlaying(false); },
      playing: function () { return state.playing; },
      controls: function (on) { bar.style.display = on ? "" : "none"; render(); },
      setSpeed: function (s) { state.speed = Number(s); speed.value = String(s); },
      show: function (key, on) { state[key] = !!on; render(); },
      showVector: function (name, on) {
        arrows.forEach(function (a) { if (a.doc.name === name) a.shown = !!on; }); render();
      },
      render: render,
      get frameCount() { return state.frameCount; },
      cameraMatrix: function () {
        camera.updateMatrixWorld();
        return {projection: camera.projectionMatrix.elements.slice(), view: camera.matrixWorldInverse.elements.slice(),
                width: size.width, height: size.height, canvas: renderer.domElement.getBoundingClientRect().toJSON()};
      },
      project: function (p) {
        var v = new THREE.Vector3().fromArray(p).project(camera);
        var r = renderer.domElement.getBoundingClientRect();
        return [r.left + (v.x + 1) / 2 * size.width, r.top + (1 - v.y) / 2 * size.height, v.z];
      },
      benchmark: function (seconds) {
        return new Promise(function (resolve) {
          var start = null, frames = 0, work = [];
          state.time = t0;
          function step(now) {
            if (start === null) start = now;
            var a = performance.now();
            state.time = t0 + ((now - start) / 1000) % Math.max(t1 - t0, 1e-300);
            render();
            work.push(performance.now() - a);
            frames++;
            if (now - start < 1000 * seconds) requestAnimationFrame(step);
            else {
              work.sort(function (x, y) { return x - y; });
              resolve({frames: frames, seconds: (now - start) / 1000, fps: (frames - 1) / ((now - start) / 1000),
                       work_ms_mean: work.reduce(function (s, x) { return s + x; }, 0) / work.length,
                       work_ms_p95: work[Math.floor(0.95 * (work.length - 1))]});
            }
          }
          requestAnimationFrame(step);
        });
      }
    };
    views.push(api);
    window.lagrangianViews = views;
    window.lagrangianView = api;
    return api;
  }

  return {mount: mount};
})();

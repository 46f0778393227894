// granum's addition to trame-vtk's vtk.js components (a Vue 3 plugin, installed as window.granum_view).
//
// <granum-sphere-impostors scale-array="radius">, placed inside a <vtk-geometry-representation>, makes
// that representation draw every point of its polydata as a sphere impostor: one screen-facing triangle
// per point whose fragments are ray-cast onto the sphere (exact silhouette, per-pixel normal and depth),
// of radius the point's value in the scale array. vtk.js draws this with its OpenGL sphere mapper, which
// trame-vtk's bundle registers for the class name "vtkSphereMapper", but the bundle leaves out the core
// vtkSphereMapper class itself, which is a vtkMapper with three more fields (radius, scaleArray,
// scaleFactor). vtk.js objects are frozen, so the component gives the representation's actor a mapper
// made on top of the representation's own (every method and the input data shared) that adds the three
// fields and the class name, before the actor is first drawn: the renderer then picks the sphere mapper.
// Compared with instanced sphere meshes (vtkGlyph3DMapper), a sphere costs 3 vertices instead of
// hundreds, which is what software WebGL (no GPU) spends its time on.
(function () {
  function capitalized(name) {
    return name.charAt(0).toUpperCase() + name.slice(1);
  }

  function sphereMapperOn(mapper, fields) {
    const sphereMapper = Object.create(mapper);
    Object.keys(fields).forEach((name) => {
      let value = fields[name];
      sphereMapper[`get${capitalized(name)}`] = () => value;
      sphereMapper[`set${capitalized(name)}`] = (v) => {
        if (value === v) {
          return false;
        }
        value = v;
        mapper.modified();
        return true;
      };
    });
    // vtk.js objects: get() with no names returns the object's model, whose classHierarchy names it
    const hierarchy = mapper.get().classHierarchy;
    if (!hierarchy.includes("vtkSphereMapper")) {
      hierarchy.push("vtkSphereMapper");
    }
    return sphereMapper;
  }

  // Occlusion culling, on software WebGL only. There every fragment of every sphere costs CPU time: the
  // impostors write their own depth (gl_FragDepth), so no hidden fragment is rejected before it is shaded,
  // and a box of 10,000 spheres is some twenty spheres deep. Before each frame the spheres that cannot be
  // seen are left out of the data drawn, found with a coarse depth buffer (cells of CELL_PX pixels) filled
  // front to back in JavaScript. A ray of the view is at angle g <= G from the view's axis, G the angle of
  // the sphere's centre from the axis plus its angular radius asin(r / d) (r its radius, d the distance of
  // its centre c from the eye, z the centre's view depth); a ray passing at distance rho = r sin(psi) from
  // c meets the sphere's near side at a view depth between z - r cos(max(0, psi - G)) and
  // z - r cos(psi + G) (the hit point is c + r (-cos(psi) w + sin(psi) n), w the ray, n normal to it):
  // * a sphere drawn occludes each cell whose four corner rays pass within r of c and inside the triangle
  //   that vtk.js draws it on (all its rays do, the angle to c being largest at a corner), down to the
  //   far bound for the largest psi of the corners;
  // * a sphere is left out when every cell it touches holds an occluder nearer than its near bound for
  //   the smallest psi of the cell's rays (the cell's centre ray's angle to c less the cell's half
  //   diagonal, which bounds the angle between two of its rays).
  // Both tests are conservative: a sphere left out has no pixel in front of the spheres drawn, so the
  // picture is the one drawn without culling. Spheres cut by the near or far clipping plane are always
  // drawn and occlude nothing. Picking is unaffected (the server casts the clicked ray). A parallel
  // projection is the same with g = 0 and distances in the view plane.
  const CELL_PX = 2;

  function unit(v) {
    const n = Math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    return [v[0] / n, v[1] / n, v[2] / n];
  }

  function cross(a, b) {
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
  }

  // (rho / r)^2 of the ray through (X, Y) of the view plane for the sphere of radius^2 r2 centred at
  // (x, y, z) in view coordinates, at distance^2 d2 from the eye: rho the ray's distance from the centre
  // (Infinity for a ray away from the centre)
  function rim2(X, Y, x, y, z, d2, r2, parallel) {
    if (parallel) {
      return ((X - x) * (X - x) + (Y - y) * (Y - y)) / r2;
    }
    const dot = X * x + Y * y + z;
    return dot > 0 ? (d2 - (dot * dot) / (X * X + Y * Y + 1)) / r2 : Infinity;
  }

  // The cells (of side `side` in the view plane, half its width halfW and half its height halfH) that the
  // silhouette of the sphere (x, y, z, r) can reach, as [i0, i1, j0, j1] in `reach`: false when none.
  // The silhouette's extent along an axis of the plane: the tangents from the eye to the circle that the
  // sphere cuts in the plane through the axis and the view direction.
  function cellsInReach(reach, x, y, z, r, halfW, halfH, side, cols, rows, parallel) {
    const extent = (q, half, cells, at) => {
      let lo = q - r;
      let hi = q + r;
      if (!parallel) {
        const phi = Math.atan2(q, z);
        const delta = Math.asin(Math.min(1, r / Math.sqrt(q * q + z * z)));
        lo = Math.tan(phi - delta);
        hi = Math.tan(phi + delta);
      }
      reach[at] = Math.max(0, Math.floor((lo + half) / side));
      reach[at + 1] = Math.min(cells - 1, Math.floor((hi + half) / side));
      return reach[at] <= reach[at + 1];
    };
    return extent(x, halfW, cols, 0) && extent(y, halfH, rows, 2);
  }

  // Scratch arrays of the culling, kept from frame to frame: a frame of 10,000 spheres would otherwise allocate
  // about a megabyte, whose garbage collection took 5.6 ms a frame. scratch(name, Type, length): the array
  // `name` of `length` items (its values are those a former frame left).
  const scratchArrays = {};

  function scratch(name, Type, length) {
    let array = scratchArrays[name];
    if (!array || array.length < length) {
      array = scratchArrays[name] = new Type(length);
    }
    return array.subarray(0, length);
  }

  // The indices of `depths` in increasing order, into `order`, as a counting sort of the depths rounded to
  // one of depths.length steps (the culling is exact in any order: a sphere processed before one that
  // hides it is merely drawn; near-sorted is fast and O(n)).
  function depthOrder(depths, order) {
    const n = depths.length;
    let lo = Infinity;
    let hi = -Infinity;
    for (let k = 0; k < n; k++) {
      if (depths[k] < lo && depths[k] > -Infinity) {   // comparisons: a NaN depth is skipped
        lo = depths[k];
      }
      if (depths[k] > hi && depths[k] < Infinity) {
        hi = depths[k];
      }
    }
    const scale = hi > lo ? (n - 1) / (hi - lo) : 0;
    const start = scratch("start", Uint32Array, n + 1).fill(0);
    const bucket = scratch("bucket", Uint32Array, n);
    for (let k = 0; k < n; k++) {
      const d = depths[k];
      const b = d >= lo && d <= hi ? Math.floor((d - lo) * scale) : d < lo ? 0 : n - 1;   // NaN: last
      bucket[k] = b;
      start[b + 1] += 1;
    }
    for (let b = 0; b < n; b++) {
      start[b + 1] += start[b];
    }
    for (let k = 0; k < n; k++) {
      order[start[bucket[k]]++] = k;
    }
  }

  // The indices (into centres (3n floats) and radii (n floats)) of the spheres that can be seen by the
  // vtk.js camera in a view of size [width, height] device pixels, nearest first (a scratch array: valid until
  // the next call).
  function visibleSpheres(centres, radii, camera, size) {
    const n = radii.length;
    const [width, height] = size;
    const eye = camera.getPosition();
    const forward = unit(camera.getDirectionOfProjection());
    const right = unit(cross(forward, camera.getViewUp()));
    const up = cross(right, forward);
    const [clipNear, clipFar] = camera.getClippingRange();
    const parallel = camera.getParallelProjection();
    // the view plane (z = 1 in view coordinates, perspective; the plane of the eye, parallel), in tangents
    // (perspective) or metres (parallel): half its height and width, a cell's side and half diagonal
    const halfH = parallel ? camera.getParallelScale() : Math.tan((camera.getViewAngle() * Math.PI) / 360);
    const halfW = (halfH * width) / height;
    const cols = Math.ceil(width / CELL_PX);
    const rows = Math.ceil(height / CELL_PX);
    const side = (2 * CELL_PX * halfW) / width;
    const halfDiagonal = Math.SQRT1_2 * side;   // an angle (perspective: bounds the angle of two rays)
    const nearest = scratch("nearest", Float64Array, cols * rows).fill(Infinity);
    let corner = scratch("corner", Float64Array, 1024);
    // view coordinates of the centres, and the nearest view depth of each sphere
    const view = scratch("view", Float64Array, 3 * n);
    const front = scratch("front", Float64Array, n);
    const order = scratch("order", Uint32Array, n);
    for (let k = 0; k < n; k++) {
      const dx = centres[3 * k] - eye[0];
      const dy = centres[3 * k + 1] - eye[1];
      const dz = centres[3 * k + 2] - eye[2];
      view[3 * k] = dx * right[0] + dy * right[1] + dz * right[2];
      view[3 * k + 1] = dx * up[0] + dy * up[1] + dz * up[2];
      view[3 * k + 2] = dx * forward[0] + dy * forward[1] + dz * forward[2];
      front[k] = view[3 * k + 2] - radii[k];
    }
    depthOrder(front, order);
    const kept = scratch("kept", Uint32Array, n);
    let count = 0;
    const reach = new Int32Array(4);   // the cells [i0, i1] x [j0, j1] a sphere's silhouette can reach
    for (let o = 0; o < n; o++) {
      const k = order[o];
      const x = view[3 * k];
      const y = view[3 * k + 1];
      const z = view[3 * k + 2];
      const r = radii[k];
      const r2 = r * r;
      const nearestPoint = front[k];
      if (!(nearestPoint > clipNear) || !(r > 0)) {   // cut by the near plane (or no size): drawn, occludes nothing
        kept[count++] = k;
        continue;
      }
      const d2 = x * x + y * y + z * z;
      const d = Math.sqrt(d2);
      if (!cellsInReach(reach, x, y, z, r, halfW, halfH, side, cols, rows, parallel)) {
        continue;   // outside the view
      }
      const i0 = reach[0];
      const i1 = reach[1];
      const j0 = reach[2];
      const j1 = reach[3];
      const widest = parallel ? 0 : Math.min(Math.PI / 2, Math.acos(z / d) + Math.asin(r / d));
      const cosWidest = Math.cos(widest);
      const sinWidest = Math.sin(widest);
      let hidden = true;
      for (let j = j0; j <= j1 && hidden; j++) {
        const Y = -halfH + (j + 0.5) * side;
        for (let i = i0; i <= i1; i++) {
          const occluder = nearest[j * cols + i];
          if (occluder < nearestPoint) {
            continue;   // hidden even at the sphere's nearest point
          }
          // the smallest rho / r of the cell's rays
          const rim = Math.sqrt(rim2(-halfW + (i + 0.5) * side, Y, x, y, z, d2, r2, parallel));
          let least;
          if (parallel) {
            least = rim - halfDiagonal / r;
          } else {
            const angle = Math.asin(Math.min(1, (rim * r) / d)) - halfDiagonal;
            least = angle > 0 ? (Math.sin(angle) * d) / r : 0;
          }
          if (!(least <= 1)) {
            continue;   // the cell misses the sphere
          }
          const psi = Math.asin(least);
          if (occluder >= z - r * (psi > widest ? Math.cos(psi - widest) : 1)) {
            hidden = false;
            break;
          }
        }
      }
      if (hidden) {
        continue;
      }
      kept[count++] = k;
      if (z + r >= clipFar) {
        continue;   // cut by the far plane: occludes nothing
      }
      // occluded cells: the (rho / r)^2 of the corners of the cells in reach, then the cells within r
      const w = i1 - i0 + 2;
      if (corner.length < w * (j1 - j0 + 2)) {
        corner = scratch("corner", Float64Array, 2 * w * (j1 - j0 + 2));
      }
      for (let j = j0; j <= j1 + 1; j++) {
        const Y = -halfH + j * side;
        for (let i = i0; i <= i1 + 1; i++) {
          corner[(j - j0) * w + (i - i0)] = rim2(-halfW + i * side, Y, x, y, z, d2, r2, parallel);
        }
      }
      // vtk.js draws a sphere on a triangle whose inscribed circle, of radius r about c facing the eye, is
      // a little inside the silhouette (at angle atan(r / d), not asin(r / d)): only rays inside it occlude
      const drawn = parallel ? 1 : d2 / (d2 + r2);
      for (let j = j0; j <= j1; j++) {
        for (let i = i0; i <= i1; i++) {
          const c = (j - j0) * w + (i - i0);
          const most = Math.max(corner[c], corner[c + 1], corner[c + w], corner[c + w + 1]);
          if (most < drawn) {
            const far = z - r * (Math.sqrt(1 - most) * cosWidest - Math.sqrt(most) * sinWidest);
            if (far < nearest[j * cols + i]) {
              nearest[j * cols + i] = far;
            }
          }
        }
      }
    }
    return kept.subarray(0, count);
  }

  // An object that answers as `base` does except for the methods given (vtk.js objects are frozen, so
  // their methods are replaced on an object made on top of them).
  function overriding(base, methods) {
    const object = Object.create(base);
    Object.keys(methods).forEach((name) => Object.defineProperty(object, name, { value: methods[name] }));
    return object;
  }

  // A stand-in for the polydata `input` (points, the point scalars and the `scaleArray` point array) that
  // holds only the spheres of each frame that can be seen: visible(input, camera, size) is the input to
  // draw, recomputed when the input, the camera or the view's size has changed.
  const redraws = [];   // the views that cull, redrawn by setCulling

  function occlusionCuller(scaleArray) {
    let source = null;
    let culled = null;
    let points;
    let scalars;
    let radii;
    let key = "";
    function stage(input) {
      source = input;
      points = input.getPoints().newClone();
      scalars = input.getPointData().getScalars().newClone();
      radii = input.getPointData().getArray(scaleArray).newClone();
      const pointData = overriding(input.getPointData(), {
        getScalars: () => scalars,
        getArray: (name) => (name === scaleArray ? radii : input.getPointData().getArray(name)),
      });
      const shown = overriding(points, { getNumberOfPoints: () => points.getNumberOfTuples() });
      culled = overriding(input, {
        getPoints: () => shown,
        getPointData: () => pointData,
        getMTime: () => Math.max(input.getMTime(), points.getMTime()),
      });
    }
    let culling = false;
    return (input, camera, size) => {
      const pointData = input.getPointData();
      const allScalars = pointData.getScalars();
      const allRadii = pointData.getArray(scaleArray);
      const stats = window.granum_view;
      if (!input.getPoints() || !allScalars || !allRadii || !stats.culling) {
        if (culling) {
          input.modified();   // the spheres drawn last were the culled ones: the renderer is to read all again
          culling = false;
        }
        stats.spheresDrawn = null;
        return input;
      }
      const allPoints = input.getPoints();
      const next = [input, allPoints, allScalars, allRadii, camera].map((o) => o.getMTime()).join(" ") + ` ${size}`;
      if (input !== source) {
        stage(input);
      } else if (culling && next === key) {
        return culled;
      }
      culling = true;
      key = next;
      const t0 = performance.now();
      const centres = allPoints.getData();
      const allR = allRadii.getData();
      const colours = allScalars.getData();
      const m = allScalars.getNumberOfComponents();
      const kept = visibleSpheres(centres, allR, camera, size);
      const xyz = new Float32Array(3 * kept.length);
      const r = new Float32Array(kept.length);
      const rgb = new colours.constructor(m * kept.length);
      for (let o = 0; o < kept.length; o++) {
        const k = kept[o];
        xyz[3 * o] = centres[3 * k];
        xyz[3 * o + 1] = centres[3 * k + 1];
        xyz[3 * o + 2] = centres[3 * k + 2];
        r[o] = allR[k];
        for (let c = 0; c < m; c++) {
          rgb[m * o + c] = colours[m * k + c];
        }
      }
      radii.setData(r, 1);
      scalars.setData(rgb, m);
      points.setData(xyz, 3);   // last: its time stamps the culled input (getMTime)
      stats.spheresDrawn = kept.length;
      stats.cullingMs += performance.now() - t0;
      stats.framesCulled += 1;
      return culled;
    };
  }

  // vtk.js's Phong lighting writes, for each light, a specular term in a branch that software WebGL takes for
  // every fragment whatever its condition (its pow() with it): the term is multiplied by the property's
  // specular coefficient, 0 unless set (the view never sets it), so left out of the sphere impostors' fragment
  // shader while that coefficient is 0 it changes no pixel. A frame of the 10,646 spheres of
  // benchmarks/view_fps.py (about 4,000 drawn after culling) took 103-114 ms of SwiftShader CPU time
  // without it, 186-207 ms with it.
  const SPECULAR_TERM = "  if \\(dot\\(normalVCVSOutput, lightDirectionVC\\d+\\) < 0\\.0\\)\\s*\\{[^}]*\\}";

  function leaveOutZeroSpecular(mapper, property) {
    let left = null;
    const update = () => {
      const leave = property.getSpecular() === 0;
      if (leave === left) {
        return;
      }
      left = leave;
      mapper.getViewSpecificProperties().OpenGL = {
        ShaderReplacements: leave
          ? [{ shaderType: "Fragment", originalValue: SPECULAR_TERM, replacementValue: "", replaceFirst: false,
            replaceAll: true }]
          : [],
      };
      mapper.modified();   // the shader is built again
    };
    update();
    property.onModified(update);
  }

  const SphereImpostors = {
    props: { scaleArray: { type: String, default: null }, radius: { type: Number, default: 1.0 } },
    setup(props) {
      // runs before the representation is mounted, i.e. before its actor is added to the renderer
      const representation = window.Vue.inject("representation");
      const view = window.Vue.inject("view");
      let mapper = sphereMapperOn(representation.mapper,
        { radius: props.radius, scaleArray: props.scaleArray, scaleFactor: 1.0 });
      if (SOFTWARE_WEBGL && props.scaleArray) {
        // the renderer reads its input through getInputData; bounds (camera, clipping range) keep all spheres
        const visible = occlusionCuller(props.scaleArray);
        redraws.push(() => view.render());
        mapper = overriding(mapper, {
          getInputData: (port) => visible(representation.mapper.getInputData(port),
            view.renderer.getActiveCamera(), view.openglRenderWindow.getSize()),
        });
      }
      representation.actor.setMapper(mapper);
      leaveOutZeroSpecular(representation.mapper, representation.actor.getProperty());
      window.Vue.watch(() => props.scaleArray, (v) => mapper.setScaleArray(v));
      window.Vue.watch(() => props.radius, (v) => mapper.setRadius(v));
      return {};
    },
    template: '<div class="granum-sphere-impostors"></div>',
  };

  // <granum-lights :lights="[{position, focalPoint, color}, ...]">, placed inside a <vtk-view>: the view's
  // renderer is lit by these lights only (scene lights, fixed in the scene, shining from the position
  // towards the focal point), instead of vtk.js's automatic headlight.
  const Lights = {
    props: { lights: { type: Array, default: () => [] } },
    setup(props) {
      const view = window.Vue.inject("view");
      function light() {
        const renderer = view.renderer;
        renderer.setAutomaticLightCreation(false);
        renderer.removeAllLights();
        props.lights.forEach(({ position, focalPoint, color }) => {
          const l = renderer.makeLight();
          l.setLightTypeToSceneLight();
          l.setPositional(false);
          l.setPosition(...position);
          l.setFocalPoint(...focalPoint);
          l.setColor(...color);
          l.setIntensity(1.0);
          renderer.addLight(l);
        });
        view.render();
      }
      window.Vue.watch(() => props.lights, light, { immediate: true });
      return {};
    },
    template: '<div class="granum-lights"></div>',
  };

  // True when WebGL is drawn by the CPU (no GPU: Chromium's SwiftShader, Mesa's llvmpipe/softpipe), as a
  // small probe context reports it (WEBGL_debug_renderer_info; false when the browser hides the name).
  function softwareWebGL() {
    const gl = document.createElement("canvas").getContext("webgl2");
    if (!gl) {
      return false;
    }
    const info = gl.getExtension("WEBGL_debug_renderer_info");
    const name = info ? String(gl.getParameter(info.UNMASKED_RENDERER_WEBGL)) : "";
    const lose = gl.getExtension("WEBGL_lose_context");
    if (lose) {
      lose.loseContext();
    }
    return /swiftshader|llvmpipe|softpipe|software/i.test(name);
  }

  // On software WebGL the page's WebGL contexts are made without multisampling: vtk.js creates its context
  // as soon as the view is built (before any child component runs), so the attribute is set where contexts
  // are made, for this page only (the view's canvas is its only WebGL canvas). On the CPU, 4x multisampling
  // costs a quarter of the CPU time of a frame of 10,000 sphere impostors (297 -> 221 ms measured); without
  // it the page samples each pixel at its centre, as saveSnapshot does. With a GPU nothing changes.
  const SOFTWARE_WEBGL = softwareWebGL();
  if (SOFTWARE_WEBGL) {
    const getContext = HTMLCanvasElement.prototype.getContext;
    HTMLCanvasElement.prototype.getContext = function (kind, attributes) {
      const webgl = kind === "webgl2" || kind === "webgl" || kind === "experimental-webgl";
      return getContext.call(this, kind, webgl ? { ...attributes, antialias: false } : attributes);
    };
  }

  window.granum_view = {
    // occlusion culling on (software WebGL only); setCulling(false) draws every sphere again (to compare
    // pictures); spheresDrawn: the spheres drawn in the last frame culled (null when not culling);
    // cullingMs: the time spent culling; framesCulled: the frames culled (one a frame drawn after the camera
    // or the data changed: a check on a frame count taken from requestAnimationFrame)
    culling: true,
    spheresDrawn: null,
    cullingMs: 0,
    framesCulled: 0,
    setCulling(on) {
      this.culling = on;
      redraws.forEach((redraw) => redraw());
    },
    install(app) {
      app.component("granum-sphere-impostors", SphereImpostors);
      app.component("granum-lights", Lights);
    },
  };
})();

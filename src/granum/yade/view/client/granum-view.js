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

  const SphereImpostors = {
    props: { scaleArray: { type: String, default: null }, radius: { type: Number, default: 1.0 } },
    setup(props) {
      // runs before the representation is mounted, i.e. before its actor is added to the renderer
      const representation = window.Vue.inject("representation");
      const mapper = sphereMapperOn(representation.mapper,
        { radius: props.radius, scaleArray: props.scaleArray, scaleFactor: 1.0 });
      representation.actor.setMapper(mapper);
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

  window.granum_view = {
    install(app) {
      app.component("granum-sphere-impostors", SphereImpostors);
      app.component("granum-lights", Lights);
    },
  };
})();

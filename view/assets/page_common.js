  // Shared by the export viewer (view/assets/index.html) and the planner of `camplace serve`
  // (serve/assets/planner.html): the build pastes this file into both pages where they say
  // CAMPLACE_PAGE_COMMON (cmake/EmbedPage.cmake), so they report errors and draw the scene's
  // frame alike.
  //
  // Errors: the page sets window.camplaceStatus first (for people and for the browser tests);
  // from here on every load error, page error, unhandled rejection and console.error lands in
  // its `errors` (console.warn in its `warnings`, where the page keeps one), published as JSON
  // in #camplace-status.
  window.camplacePublish = function () {
    var status = document.getElementById('camplace-status');
    if (status) status.textContent = JSON.stringify(window.camplaceStatus);
    var errors = document.getElementById('camplace-errors');
    if (errors) errors.textContent = window.camplaceStatus.errors.join('\n');
  };
  (function () {
    var s = window.camplaceStatus;
    var text = function (args) { return Array.prototype.map.call(args, String).join(' '); };
    var originalError = console.error, originalWarn = console.warn;
    console.error = function () {
      s.errors.push('console.error: ' + text(arguments));
      window.camplacePublish();
      originalError.apply(console, arguments);
    };
    if (s.warnings) {
      console.warn = function () {
        s.warnings.push(text(arguments));
        window.camplacePublish();
        originalWarn.apply(console, arguments);
      };
    }
    // Capture phase: also a <script src> that fails to load.
    window.addEventListener('error', function (e) {
      var target = e.target;
      if (target && target !== window && (target.src || target.href)) {
        s.errors.push('cannot load ' + (target.src || target.href));
      } else {
        s.errors.push('error: ' + (e.message || String(e.error)));
      }
      window.camplacePublish();
    }, true);
    window.addEventListener('unhandledrejection', function (e) {
      s.errors.push('unhandled rejection: ' + String(e.reason));
      window.camplacePublish();
    });
  })();

  // The frame, once three.js and OrbitControls have loaded: a renderer on `canvas`, lights, the
  // outline of the area S ({min, max}, m), and a camera orbiting S's centre, first seen from
  // beyond S's minimum corner, above it. camplace's world (z up) is drawn in three.js's (y up):
  // (x, y, z) → (x, z, −y). The far plane lies `farDiagonals` of S's diagonal away. On a wide
  // window the view is centred in the part the #panel leaves free.
  window.camplaceFrame = function (canvas, area, farDiagonals) {
    var frame = {};
    frame.toY = function (p) { return new THREE.Vector3(p[0], p[2], -p[1]); };
    frame.fromY = function (v) { return [v.x, -v.z, v.y]; };
    var renderer = new THREE.WebGLRenderer({ canvas: canvas, antialias: true });
    renderer.setPixelRatio(window.devicePixelRatio || 1);
    renderer.setClearColor(0xdde4ec, 1);
    var scene = new THREE.Scene();
    scene.add(new THREE.HemisphereLight(0xffffff, 0x7a8594, 0.85));
    var sun = new THREE.DirectionalLight(0xffffff, 0.55);
    sun.position.set(3, 10, 6);
    scene.add(sun);
    var box = new THREE.Box3().setFromPoints([frame.toY(area.min), frame.toY(area.max)]);
    var areaOutline = new THREE.Box3Helper(box, new THREE.Color(0x44505c));
    scene.add(areaOutline);
    var center = box.getCenter(new THREE.Vector3());
    var diagonal = box.getSize(new THREE.Vector3()).length();
    var camera = new THREE.PerspectiveCamera(40, 1, diagonal / 1000, diagonal * farDiagonals);
    camera.position.copy(center).add(
        frame.toY([-0.65 * diagonal, -1.25 * diagonal, 0.9 * diagonal]));
    var controls = new THREE.OrbitControls(camera, canvas);
    controls.target.copy(center);
    controls.update();
    frame.render = function () { renderer.render(scene, camera); };
    controls.addEventListener('change', frame.render);
    frame.resize = function () {
      var w = window.innerWidth, h = Math.max(window.innerHeight, 1);
      renderer.setSize(w, h);
      var shift = w > 800 ? document.getElementById('panel').offsetWidth : 0;
      camera.aspect = (w + shift) / h;
      camera.setViewOffset(w + shift, h, 0, 0, w, h);
      camera.updateProjectionMatrix();
      frame.render();
    };
    window.addEventListener('resize', frame.resize);
    frame.renderer = renderer;
    frame.scene = scene;
    frame.camera = camera;
    frame.controls = controls;
    frame.box = box;
    frame.areaOutline = areaOutline;
    frame.diagonal = diagonal;
    return frame;
  };

// tether's motion player (docs/view.md): draws the run described by the JSON in #tether-data with three.js and
// plays its frames, with a plot of one of its series and its events beside. Bodies are groups posed frame by frame;
// their shapes (or glyphs), joint anchors and axes and markers are children in body coordinates; distance constraints
// are rods redrawn each frame. The page starts playing, looping; VIEW.html#t=SECONDS opens it paused at that time.
// #tether-probe holds, after each drawing, the time, the frame, the series plotted and every body's origin and every
// event's place shown in canvas pixels (for the browser tests).
(function() {
'use strict';
var data = JSON.parse(document.getElementById('tether-data').textContent);
var drawing = data.drawing, frames = data.frames;
var view = document.getElementById('tether-view');
var scale = drawing.scale > 0 ? drawing.scale : 1;
var planar = drawing.dimension === 2;

var renderer = new THREE.WebGLRenderer({antialias: true, preserveDrawingBuffer: true});
renderer.setPixelRatio(window.devicePixelRatio || 1);
renderer.setClearColor(0xf4f4f4);
view.appendChild(renderer.domElement);
var scene = new THREE.Scene();
var camera = new THREE.PerspectiveCamera(40, 1, scale / 1000, scale * 1000);
camera.up.set(0, planar ? 1 : 0, planar ? 0 : 1);  // z up in 3D; the xy plane faces the camera in 2D
scene.add(new THREE.HemisphereLight(0xffffff, 0x888888, 0.9));
var sun = new THREE.DirectionalLight(0xffffff, 0.5);
sun.position.set(1, -2, 3);
scene.add(sun);

// the world frame and a floor grid in the xy plane
var axes = new THREE.AxesHelper(scale / 2);
scene.add(axes);
var grid = new THREE.GridHelper(scale * 10, 20, 0xbbbbbb, 0xdddddd);
grid.rotation.x = Math.PI / 2;
scene.add(grid);

var palette = [0x4e79a7, 0xf28e2b, 0xe15759, 0x76b7b2, 0x59a14f, 0xedc948, 0xb07aa1, 0xff9da7, 0x9c755f];
function material(color, opacity) {
  var m = new THREE.MeshLambertMaterial({color: color});
  if (opacity < 1) {
    m.transparent = true;
    m.opacity = opacity;
  }
  return m;
}
function quaternion(q) {
  return new THREE.Quaternion(q[1], q[2], q[3], q[0]);
}
function vector(x) {
  return new THREE.Vector3(x[0], x[1], x[2]);
}

// A solid in its shape frame: sphere, capsule (along x), box, or a plane (normal z in 3D, y in 2D).
function solid(shape, color) {
  var opacity = shape.contact === false ? 0.5 : 1;
  if (shape.type === 'sphere')
    return new THREE.Mesh(new THREE.SphereBufferGeometry(shape.radius, 24, 16), material(color, opacity));
  if (shape.type === 'box') {
    return new THREE.Mesh(
        new THREE.BoxBufferGeometry(shape.size[0], shape.size[1], shape.size[2]), material(color, opacity));
  }
  if (shape.type === 'capsule') {
    var capsule = new THREE.Group();
    var tube = new THREE.Mesh(
        new THREE.CylinderBufferGeometry(shape.radius, shape.radius, shape.length, 24), material(color, opacity));
    tube.rotation.z = Math.PI / 2;  // three's cylinder runs along y, tether's capsule along x
    capsule.add(tube);
    [-1, 1].forEach(function(side) {
      var cap = new THREE.Mesh(new THREE.SphereBufferGeometry(shape.radius, 24, 16), material(color, opacity));
      cap.position.x = side * shape.length / 2;
      capsule.add(cap);
    });
    return capsule;
  }
  var plane = planar ? new THREE.BoxBufferGeometry(scale * 10, scale / 100, scale / 100) :
                       new THREE.PlaneBufferGeometry(scale * 10, scale * 10);
  var floor = new THREE.Mesh(plane, material(0xcccccc, 0.6));
  floor.material.side = THREE.DoubleSide;
  return floor;
}
function placed(object, shape) {
  object.position.copy(vector(shape.position));
  object.quaternion.copy(quaternion(shape.rotation));
  return object;
}

var world = new THREE.Group();
scene.add(world);
var bodies = drawing.bodies.map(function(body, i) {
  var group = new THREE.Group();
  group.name = body.name;
  if (body.glyph) {  // translucent: a glyph is the body's inertia, not its outline, and hides no joint
    var glyph = solid(Object.assign({contact: false}, body.glyph), palette[i % palette.length]);
    group.add(placed(glyph, {position: [0, 0, 0], rotation: body.glyph.rotation || [1, 0, 0, 0]}));
  }
  scene.add(group);
  return group;
});
function holder(index) {
  return index >= 0 ? bodies[index] : world;
}
drawing.shapes.forEach(function(shape) {
  var color = shape.body >= 0 ? palette[shape.body % palette.length] : 0xaaaaaa;
  holder(shape.body).add(placed(solid(shape, color), shape));
});
// a recording beside the run (tether view --compare): every body again, grey and translucent, posed by its frames
// (a recording of some columns only has no poses: its series are plotted, no ghost is drawn)
var ghost = data.ghost, posedGhost = ghost && ghost.frames.poses.length > 0;
var ghosts = !posedGhost ? [] : drawing.bodies.map(function(body) {
  var group = new THREE.Group();
  if (body.glyph) {
    var glyph = solid(Object.assign({contact: false}, body.glyph), 0x777777);
    group.add(placed(glyph, {position: [0, 0, 0], rotation: body.glyph.rotation || [1, 0, 0, 0]}));
  }
  scene.add(group);
  return group;
});
drawing.shapes.forEach(function(shape) {
  if (posedGhost && shape.body >= 0)
    ghosts[shape.body].add(placed(solid(Object.assign({}, shape, {contact: false}), 0x777777), shape));
});
function dot(radius, color) {
  return new THREE.Mesh(new THREE.SphereBufferGeometry(radius, 12, 8), material(color, 1));
}
function line(from, to, color) {
  var geometry = new THREE.BufferGeometry().setFromPoints([from, to]);
  return new THREE.Line(geometry, new THREE.LineBasicMaterial({color: color}));
}
var rods = [];
drawing.joints.forEach(function(joint) {
  if (joint.type === 'distance') {
    var rod = line(new THREE.Vector3(), new THREE.Vector3(), 0x333333);
    rod.userData = joint;
    scene.add(rod);
    rods.push(rod);
    return;
  }
  [joint.a, joint.b].forEach(function(end) {
    var anchor = dot(scale / 60, 0x222222);
    anchor.position.copy(vector(end.point));
    holder(end.body).add(anchor);
    if (end.body >= 0 && vector(end.point).lengthSq() > 0) {  // a bone (none where the anchor is the centre)
      holder(end.body).add(line(new THREE.Vector3(), vector(end.point), 0x666666));
    }
  });
  if (joint.axis) {
    var a = vector(joint.a.point), axis = vector(joint.axis).multiplyScalar(scale / 8);
    holder(joint.a.body).add(line(a.clone().sub(axis), a.clone().add(axis), 0xd62728));
  }
});
drawing.markers.forEach(function(marker) {
  var point = dot(scale / 80, 0x2ca02c);
  point.position.copy(vector(marker.point));
  holder(marker.body).add(point);
});

// the frames
var count = frames.times.length;
function place(groups, p) {
  groups.forEach(function(group, b) {
    group.position.set(p[7 * b], p[7 * b + 1], p[7 * b + 2]);
    group.quaternion.set(p[7 * b + 4], p[7 * b + 5], p[7 * b + 6], p[7 * b + 3]);
    group.updateMatrixWorld(true);
  });
}
function pose(frame) {
  place(bodies, frames.poses[frame]);
  if (posedGhost) place(ghosts, ghost.frames.poses[frameIn(ghost.frames.times, frames.times[frame])]);
  rods.forEach(function(rod) {
    var ends = [rod.userData.a, rod.userData.b].map(function(end) {
      return holder(end.body).localToWorld(vector(end.point));
    });
    rod.geometry.setFromPoints(ends);
  });
}
// the frame shown at time t: the last at or before it (the first if there is none)
function frameIn(times, t) {
  var low = 0, high = times.length - 1;
  while (low < high) {
    var middle = (low + high + 1) >> 1;
    if (times[middle] <= t)
      low = middle;
    else
      high = middle - 1;
  }
  return low;
}
function frameAt(t) {
  return frameIn(frames.times, t);
}

// the events' places, each shown for a quarter of a second of frames from its own: a dot where it happened (an
// impact's red, a release's blue, stick green, slip orange) and an impact's impulse as an arrow along the contact's
// normal, into the body it pushes (the largest impulse half the view's scale long)
var events = data.events;
var eventColors = {impact: 0xd62728, release: 0x1f77b4, stick: 0x2ca02c, slip: 0xff7f0e};
var largestImpulse = events.reduce(function(largest, event) {
  return Math.max(largest, event.impulse);
}, 0);
var places = events.map(function(event) {
  var place = new THREE.Group(), color = eventColors[event.kind] || 0x333333;
  place.add(dot(scale / 40, color));
  var normal = vector(event.normal);
  if (event.impulse > 0 && normal.lengthSq() > 0) {
    var length = scale / 2 * event.impulse / largestImpulse;
    place.add(new THREE.ArrowHelper(normal.normalize(), new THREE.Vector3(), length, color, length / 4, length / 8));
  }
  place.position.copy(vector(event.point));
  place.visible = false;
  place.userData.frame = frameAt(event.t);
  scene.add(place);
  return place;
});
var placeFrames = 15;

// the camera looks at everything the bodies sweep, from the side (3D) or the front (2D)
var box = new THREE.Box3();
frames.poses.forEach(function(p) {
  for (var b = 0; b < bodies.length; ++b) box.expandByPoint(new THREE.Vector3(p[7 * b], p[7 * b + 1], p[7 * b + 2]));
});
if (box.isEmpty()) box.expandByPoint(new THREE.Vector3());
box.expandByScalar(scale / 2);  // and the bodies themselves, up to the view's scale
var controls = new THREE.OrbitControls(camera, renderer.domElement);
controls.enableRotate = !planar;
function resetView() {
  var centre = box.getCenter(new THREE.Vector3()), radius = box.getSize(new THREE.Vector3()).length() / 2;
  var distance = radius / Math.sin(camera.fov * Math.PI / 360);
  controls.target.copy(centre);
  camera.position.copy(centre).add(
      planar ? new THREE.Vector3(0, 0, distance) : new THREE.Vector3(distance * 0.6, -distance * 0.75, distance * 0.3));
  camera.lookAt(centre);
  controls.update();
}

// the controls
var slider = document.getElementById('tether-time'), clock = document.getElementById('tether-clock');
var play = document.getElementById('tether-play'), speed = document.getElementById('tether-speed');
var probe = document.getElementById('tether-probe');
slider.max = String(count - 1);
var t0 = frames.times[0], t1 = frames.times[count - 1];
var time = t0, playing = true, frame = 0, clockStart = null;
var hash = /#t=([-+0-9.eE]+)/.exec(window.location.hash);
if (hash) {
  time = Math.min(Math.max(parseFloat(hash[1]), t0), t1);
  playing = false;
}
// the plot beside the view: one series against time, the events as dashed lines, a cursor at the time shown
var series = data.series;
var side = document.getElementById('tether-side'), chooser = document.getElementById('tether-series');
var plot = document.getElementById('tether-plot'), list = document.getElementById('tether-events');
var marks = document.getElementById('tether-marks');
side.hidden = series.names.length === 0 && events.length === 0;
series.names.forEach(function(name, k) {
  var option = document.createElement('option');
  option.value = String(k);
  option.textContent = name;
  chooser.appendChild(option);
});
// a joint's coordinate first, else the energy, else the first series
var preferred = series.names.findIndex(function(name) {
  return /\.(angle|displacement)$/.test(name);
});
if (preferred < 0) preferred = series.names.indexOf('energy');
chooser.value = String(Math.max(preferred, 0));
document.getElementById('tether-events-title').hidden = events.length === 0;
events.forEach(function(event) {
  var item = document.createElement('li');
  item.textContent = event.t.toFixed(4) + ' s  ' + event.kind + '  ' + event.constraint +
      (event.impulse > 0 ? '  P = ' + event.impulse.toPrecision(3) + ' ' + event.unit : '');
  item.addEventListener('click', function() {
    playing = false;
    time = event.t;
    show();
  });
  list.appendChild(item);
  var mark = document.createElement('option');
  mark.value = String(frameAt(event.t));
  marks.appendChild(mark);
});
function drawPlot() {
  if (side.hidden) return;
  var width = plot.clientWidth, height = plot.clientHeight, ratio = window.devicePixelRatio || 1;
  if (plot.width !== width * ratio || plot.height !== height * ratio) {
    plot.width = width * ratio;
    plot.height = height * ratio;
  }
  var g = plot.getContext('2d');
  g.setTransform(ratio, 0, 0, ratio, 0, 0);
  g.clearRect(0, 0, width, height);
  var k = series.names.length ? parseInt(chooser.value || '0', 10) : -1;
  var low = Infinity, high = -Infinity;
  if (k >= 0) {
    series.values.forEach(function(row) {
      if (row[k] !== null) {
        low = Math.min(low, row[k]);
        high = Math.max(high, row[k]);
      }
    });
  }
  if (!(high > low)) {
    low = (isFinite(low) ? low : 0) - 1;
    high = low + 2;
  }
  var left = 56, right = width - 8, top = 8, bottom = height - 22;
  function x(t) {
    return left + (t - t0) / Math.max(t1 - t0, 1e-12) * (right - left);
  }
  function y(v) {
    return bottom - (v - low) / (high - low) * (bottom - top);
  }
  g.strokeStyle = '#999';
  g.strokeRect(left, top, right - left, bottom - top);
  g.fillStyle = '#333';
  g.font = '11px sans-serif';
  function label(v) {  // round-off about zero is zero
    return Math.abs(v) < 1e-9 * (high - low) ? '0' : v.toPrecision(4);
  }
  g.fillText(label(high), 2, top + 10);
  g.fillText(label(low), 2, bottom);
  g.fillText(t0.toFixed(2) + ' s', left, height - 6);
  g.fillText(t1.toFixed(2) + ' s', right - 40, height - 6);
  g.setLineDash([4, 3]);
  g.strokeStyle = '#aaa';
  events.forEach(function(event) {
    g.beginPath();
    g.moveTo(x(event.t), top);
    g.lineTo(x(event.t), bottom);
    g.stroke();
  });
  g.setLineDash([]);
  // one run's column c against its frames' times, skipping the frames that do not record it
  function polyline(run, c, color, dash) {
    g.strokeStyle = color;
    g.setLineDash(dash);
    g.beginPath();
    var pen = false;
    run.series.values.forEach(function(row, f) {
      if (row[c] === null) return;
      if (pen)
        g.lineTo(x(run.frames.times[f]), y(row[c]));
      else
        g.moveTo(x(run.frames.times[f]), y(row[c]));
      pen = true;
    });
    g.stroke();
    g.setLineDash([]);
  }
  if (k >= 0) polyline(data, k, '#4e79a7', []);
  var twin = ghost && k >= 0 ? ghost.series.names.indexOf(series.names[k]) : -1;  // the recording's same column
  if (twin >= 0) polyline(ghost, twin, '#777', [5, 3]);
  g.strokeStyle = '#d62728';
  g.beginPath();
  g.moveTo(x(frames.times[frame]), top);
  g.lineTo(x(frames.times[frame]), bottom);
  g.stroke();
}
chooser.addEventListener('change', function() {
  drawPlot();
});

// a point of the world in canvas pixels
function pixel(point) {
  var p = point.clone().project(camera);
  return [(p.x + 1) / 2 * renderer.domElement.clientWidth, (1 - p.y) / 2 * renderer.domElement.clientHeight];
}
function show() {
  frame = frameAt(time);
  pose(frame);
  places.forEach(function(place) {
    place.visible = frame >= place.userData.frame && frame < place.userData.frame + placeFrames;
  });
  slider.value = String(frame);
  clock.textContent = 't = ' + frames.times[frame].toFixed(3) + ' s';
  play.textContent = playing ? 'Pause' : 'Play';
  renderer.render(scene, camera);
  drawPlot();
  function origin(group) {
    return pixel(group.getWorldPosition(new THREE.Vector3()));
  }
  probe.textContent = JSON.stringify({
    time: frames.times[frame],
    frame: frame,
    frames: count,
    plotted: series.names[parseInt(chooser.value, 10)] || null,
    ghosts: ghosts.map(origin),
    bodies: bodies.map(origin),
    places: places
                .filter(function(place) {
                  return place.visible;
                })
                .map(origin)
  });
}
function resize() {
  var width = view.clientWidth, height = view.clientHeight;
  renderer.setSize(width, height);
  camera.aspect = width / height;
  camera.updateProjectionMatrix();
  show();
}
slider.addEventListener('input', function() {
  playing = false;
  time = frames.times[parseInt(slider.value, 10)];
  show();
});
play.addEventListener('click', function() {
  playing = !playing;
  if (playing && frame === count - 1) time = t0;
  clockStart = null;
  show();
});
document.getElementById('tether-reset').addEventListener('click', function() {
  resetView();
  show();
});
controls.addEventListener('change', function() {
  if (!playing) renderer.render(scene, camera);
});
window.addEventListener('resize', resize);
function tick(now) {
  if (playing) {
    if (clockStart !== null) time += (now - clockStart) / 1000 * parseFloat(speed.value);
    clockStart = now;
    if (time > t1) time = t0;  // loops
    show();
  } else {
    clockStart = null;
  }
  window.requestAnimationFrame(tick);
}
resetView();
resize();
window.requestAnimationFrame(tick);
})();

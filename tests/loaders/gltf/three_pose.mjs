// Poses a glTF file's animations with three.js (GLTFLoader and AnimationMixer), as an independent reference for
// sgkit's AnimationPlayer.
//
//   node three_pose.mjs NODE_MODULES_DIR FILE TIMES
//
// For each animation of FILE, played once and held at its end (LoopOnce, clampWhenFinished), at TIMES evenly spaced
// times from 0 to its duration: every glTF node's world matrix (column-major, 16 numbers) and each mesh node's morph
// weights. Prints one JSON object: {"animations": [{"name", "duration", "times": [...], "nodes": {index: [[16] per
// time]}, "weights": {index: [[...] per time]}}]}. Images are left out (three.js reads them through the DOM) and
// external buffers are read from the file's directory. Exits 2 on bad usage, 1 when three.js cannot load the file.
import path from "path";
import fs from "fs/promises";

const [modules, file, timesArg] = process.argv.slice(2);
if (!modules || !file || !timesArg) {
  console.error("usage: node three_pose.mjs NODE_MODULES_DIR FILE TIMES");
  process.exit(2);
}
// three.js's FileLoader reports progress with the browser's ProgressEvent (data: URIs are fetched too).
globalThis.ProgressEvent ??= class ProgressEvent {
  constructor(type, init = {}) {
    Object.assign(this, init, { type });
  }
};
const THREE = await import(path.join(path.resolve(modules), "three", "build", "three.module.js"));
const { GLTFLoader } = await import(
  path.join(path.resolve(modules), "three", "examples", "jsm", "loaders", "GLTFLoader.js")
);

// The file as JSON with its buffers embedded and its images dropped: what three.js reads under node.
async function prepare(file) {
  const bytes = await fs.readFile(file);
  const dir = path.dirname(path.resolve(file));
  let json, bin = null;
  if (bytes.readUInt32LE(0) === 0x46546c67) {  // "glTF": a GLB's JSON chunk, then its BIN chunk
    const jsonLength = bytes.readUInt32LE(12);
    json = JSON.parse(bytes.subarray(20, 20 + jsonLength).toString("utf8"));
    const at = 20 + jsonLength;
    if (at + 8 <= bytes.length) bin = bytes.subarray(at + 8, at + 8 + bytes.readUInt32LE(at));
  } else {
    json = JSON.parse(bytes.toString("utf8"));
  }
  for (const [i, b] of (json.buffers ?? []).entries()) {
    if (b.uri === undefined && i === 0 && bin) b.uri = "data:application/octet-stream;base64," + bin.toString("base64");
    else if (b.uri && !b.uri.startsWith("data:"))
      b.uri =
        "data:application/octet-stream;base64," +
        (await fs.readFile(path.join(dir, decodeURIComponent(b.uri)))).toString("base64");
  }
  for (const m of json.materials ?? []) {
    delete m.normalTexture;
    delete m.occlusionTexture;
    delete m.emissiveTexture;
    if (m.pbrMetallicRoughness) {
      delete m.pbrMetallicRoughness.baseColorTexture;
      delete m.pbrMetallicRoughness.metallicRoughnessTexture;
    }
    delete m.extensions;
  }
  delete json.textures;
  delete json.images;
  delete json.samplers;
  return JSON.stringify(json);
}

const text = await prepare(file).catch((e) => {
  console.error(`${file}: ${e.message}`);
  process.exit(1);
});
const gltf = await new Promise((resolve, reject) => new GLTFLoader().parse(text, "", resolve, reject)).catch((e) => {
  console.error(`${file}: three.js cannot load it: ${e.message ?? e}`);
  process.exit(1);
});

// The three.js object of each glTF node.
const byNode = new Map();
gltf.scene.traverse((o) => {
  const a = gltf.parser.associations.get(o);
  if (a && a.nodes !== undefined && !byNode.has(a.nodes)) byNode.set(a.nodes, o);
});
const morphed = (o) => {
  let w = null;
  o.traverse((c) => {
    if (!w && c.morphTargetInfluences) w = Array.from(c.morphTargetInfluences);
  });
  return w;
};

// glTF's rotation keys are unit quaternions; a file's may be a little off (Debian's simple_skin: |q| = 1.00023).
// sgkit normalises them, so that a rotation stays a rotation; three.js slerps and composes them as they are, into
// a matrix scaled by |q|^2. The reference takes them normalised too (STEP and LINEAR keys: a cubic spline's tangents
// are not quaternions, and both sides normalise its result).
for (const clip of gltf.animations)
  for (const track of clip.tracks) {
    if (track.ValueTypeName !== "quaternion" || track.values.length !== track.times.length * 4) continue;
    for (let k = 0; k < track.values.length; k += 4) {
      const q = track.values.subarray(k, k + 4);
      const n = Math.hypot(q[0], q[1], q[2], q[3]);
      if (n > 0) for (let c = 0; c < 4; ++c) q[c] /= n;
    }
  }

const count = Math.max(2, parseInt(timesArg, 10));
const result = { animations: [] };
for (const clip of gltf.animations) {
  const mixer = new THREE.AnimationMixer(gltf.scene);
  const action = mixer.clipAction(clip);
  action.setLoop(THREE.LoopOnce, 1);
  action.clampWhenFinished = true;
  action.play();
  const entry = { name: clip.name, duration: clip.duration, times: [], nodes: {}, weights: {} };
  for (let k = 0; k < count; ++k) {
    const t = (clip.duration * k) / (count - 1);
    mixer.setTime(t);
    gltf.scene.updateMatrixWorld(true);
    entry.times.push(t);
    for (const [i, o] of byNode) {
      (entry.nodes[i] ??= []).push(Array.from(o.matrixWorld.elements));
      const w = morphed(o);
      if (w) (entry.weights[i] ??= []).push(w);
    }
  }
  action.stop();
  mixer.uncacheRoot(gltf.scene);
  result.animations.push(entry);
}
console.log(JSON.stringify(result));

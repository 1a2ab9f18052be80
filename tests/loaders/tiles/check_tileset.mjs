// Reads a tileset written by sg::writeTileset with CesiumGS's 3d-tiles-tools (its own traversal and resource
// resolution, as a third-party reader) and validates every content with the Khronos glTF validator.
//
//   node check_tileset.mjs NODE_MODULES_DIR TILESET_JSON
//
// Prints one line of JSON (tiles, contents, validator errors and warnings, problems, and `finals`: each tile's
// final geometric error and box half-axes, sorted, which do not depend on the tiles' frames) and exits 1 when any tile
// or content is unreadable, a glb has a validator error, or a child's geometric error exceeds its parent's.
import { createRequire } from "module";
import path from "path";
import fs from "fs";

const [modules, tilesetPath] = process.argv.slice(2);
if (!modules || !tilesetPath) {
  console.error("usage: node check_tileset.mjs NODE_MODULES_DIR TILESET_JSON");
  process.exit(2);
}
const require = createRequire(path.join(path.resolve(modules), "noop.js"));
const tools = require("3d-tiles-tools");
const validator = await import(path.join(path.resolve(modules), "gltf-validator", "module.mjs"));

const dir = path.dirname(path.resolve(tilesetPath));
const resolver = tools.ResourceResolvers.createFileResourceResolver(dir);
const tileset = JSON.parse(fs.readFileSync(tilesetPath, "utf8"));
const traverser = new tools.TilesetTraverser(dir, resolver, { depthFirst: true });

const summary = { tiles: 0, contents: 0, errors: 0, warnings: 0, problems: [], finals: [] };
const contentUris = [];
await traverser.traverse(tileset, async (tile) => {
  // A tile with implicit tiling is visited twice: as written (its content a template) and as the implicit root.
  if (tile.asRawTile().implicitTiling) return true;
  summary.tiles++;
  // Final tiles: an implicit tile's metadata semantics (TILE_GEOMETRIC_ERROR, TILE_BOUNDING_BOX) applied.
  const final = tile.asFinalTile();
  const parent = tile.getParent();
  if (parent && final.geometricError > parent.asFinalTile().geometricError)
    summary.problems.push(`${tile.path}: geometricError ${final.geometricError} above its parent's`);
  const box = final.boundingVolume.box ?? [];
  summary.finals.push([final.geometricError, ...box.slice(3)].map((v) => v.toFixed(6)).join(" "));
  for (const content of tile.getFinalContents()) contentUris.push(content.uri);
  return true;
});
for (const uri of contentUris) {
  const data = await resolver.resolveData(uri);
  if (!data) {
    summary.problems.push(`${uri}: cannot be read`);
    continue;
  }
  summary.contents++;
  const report = await validator.validateBytes(new Uint8Array(data), { maxIssues: 100 });
  summary.errors += report.issues.numErrors;
  summary.warnings += report.issues.numWarnings;
  if (report.issues.numErrors > 0)
    summary.problems.push(`${uri}: ${report.issues.messages.filter((m) => m.severity === 0).map((m) => `${m.pointer}: ${m.message}`).slice(0, 3).join("; ")}`);
}
summary.finals.sort();
console.log(JSON.stringify(summary));
process.exit(summary.problems.length || summary.errors ? 1 : 0);

// Validates glTF files (.gltf with their external buffers and images, or .glb) with the Khronos glTF validator.
//
//   node validate_gltf.mjs NODE_MODULES_DIR FILE...
//
// Prints one line of JSON per file: {"file", "errors", "warnings", "messages" and "warningMessages": the first
// few of each}. External resources are read from the file's directory; URIs with a scheme (http:, https:) are not
// fetched, and the validator reports them as unreadable. Exits 2 on bad usage only: a file's errors are data, not a failure.
import path from "path";
import fs from "fs/promises";

const [modules, ...files] = process.argv.slice(2);
if (!modules || files.length === 0) {
  console.error("usage: node validate_gltf.mjs NODE_MODULES_DIR FILE...");
  process.exit(2);
}
const validator = await import(path.join(path.resolve(modules), "gltf-validator", "module.mjs"));

for (const file of files) {
  const dir = path.dirname(path.resolve(file));
  const line = { file, errors: 0, warnings: 0, messages: [] };
  try {
    const data = new Uint8Array(await fs.readFile(file));
    const report = await validator.validateBytes(data, {
      uri: path.basename(file),
      maxIssues: 50,
      externalResourceFunction: async (uri) => {
        if (/^[a-z][a-z0-9+.-]*:/i.test(uri)) throw new Error(`${uri}: not fetched`);
        return new Uint8Array(await fs.readFile(path.join(dir, decodeURIComponent(uri))));
      },
    });
    line.errors = report.issues.numErrors;
    line.warnings = report.issues.numWarnings;
    const first = (severity) =>
      report.issues.messages
        .filter((m) => m.severity === severity)
        .slice(0, 3)
        .map((m) => `${m.pointer ?? ""}: ${m.message}`);
    line.messages = first(0);
    line.warningMessages = first(1);
  } catch (e) {
    // The validator throws on input it cannot start on (not JSON, not glTF): one error.
    line.errors = 1;
    line.messages = [String(e && e.message ? e.message : e)];
  }
  console.log(JSON.stringify(line));
}

// Validates glTF files with the Khronos glTF-Validator (npm `gltf-validator`): prints one
// summary line per file and exits 1 when any has an error or a warning.
//   node tools/validate-gltf.mjs FILE.glb FILE.gltf ...
// (NODE_PATH may point at the node_modules that holds gltf-validator.)
import { createRequire } from "module";
import { readFileSync } from "fs";
const require = createRequire(import.meta.url);
const validator = require("gltf-validator");
let bad = 0;
for (const file of process.argv.slice(2)) {
  const report = await validator.validateBytes(new Uint8Array(readFileSync(file)), {
    maxIssues: 50,
  });
  const { numErrors, numWarnings, numInfos, numHints } = report.issues;
  console.log(`${file}: ${numErrors} errors, ${numWarnings} warnings, ${numInfos} infos, ${numHints} hints`);
  for (const m of report.issues.messages) {
    if (m.severity <= 1) console.log(`  ${m.code}: ${m.message} (${m.pointer ?? ""})`);
  }
  if (numErrors > 0 || numWarnings > 0) bad++;
}
process.exit(bad ? 1 : 0);

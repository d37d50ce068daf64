// Validates glTF files with the Khronos glTF validator: exits 1 on any error (and prints the
// messages), 0 when every file is valid. Usage: node validate-gltf.mjs FILE.glb ...
import { readFile } from 'node:fs/promises';
import validator from 'gltf-validator';

let failed = false;
for (const path of process.argv.slice(2)) {
  const bytes = new Uint8Array(await readFile(path));
  const report = await validator.validateBytes(bytes, { maxIssues: 50 });
  const { numErrors, numWarnings, messages } = report.issues;
  const info = report.info || {};
  console.log(`${path}: ${numErrors} errors, ${numWarnings} warnings; ${info.animationCount ?? 0} animations, ` +
              `${info.nodeCount ?? '?'} nodes, ${info.totalVertexCount ?? '?'} vertices`);
  for (const m of messages) if (m.severity <= 1) console.log(`  ${m.severity === 0 ? 'error' : 'warning'} ${m.code} ${m.pointer ?? ''}: ${m.message}`);
  if (numErrors > 0) failed = true;
}
process.exit(failed ? 1 : 0);

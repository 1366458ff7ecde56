// Validates glTF files (.glb, .vrm, and .gltf with the files its URIs name
// beside it) with the Khronos glTF validator.
//
//   node validate.mjs FILE.glb...
//
// Prints one line per file (errors, warnings, infos, hints; then every issue
// that is an error or a warning) and exits 1 when any file has an error or a
// warning, 2 when a file cannot be read.
import { readFile } from 'node:fs/promises';
import { basename, dirname, resolve } from 'node:path';
import validator from 'gltf-validator';

const SEVERITY = ['error', 'warning', 'info', 'hint'];
const files = process.argv.slice(2);
if (files.length === 0) {
  console.error('usage: node validate.mjs FILE.glb...');
  process.exit(2);
}
let failed = false;
for (const file of files) {
  let bytes;
  try {
    bytes = new Uint8Array(await readFile(file));
  } catch (e) {
    console.error(`${file}: ${e.message}`);
    process.exit(2);
  }
  const report = await validator.validateBytes(bytes, {
    uri: basename(file),
    maxIssues: 0,
    // A .gltf's buffers and images, read from its folder.
    externalResourceFunction: async (uri) =>
      new Uint8Array(await readFile(resolve(dirname(file), decodeURIComponent(uri)))),
  });
  const { numErrors, numWarnings, numInfos, numHints, messages } = report.issues;
  const info = report.info ?? {};
  console.log(
    `${file}: ${numErrors} errors, ${numWarnings} warnings, ${numInfos} infos, ${numHints} hints` +
      ` (${info.totalVertexCount ?? '?'} vertices, ${info.totalTriangleCount ?? '?'} triangles,` +
      ` ${info.animationCount ?? '?'} animations, generator ${info.generator ?? '?'})`,
  );
  for (const m of messages) {
    const tag = SEVERITY[m.severity] ?? String(m.severity);
    if (m.severity <= 1 || process.env.GLTF_CHECK_VERBOSE) {
      console.log(`  ${tag} ${m.code} at ${m.pointer ?? m.offset ?? ''}: ${m.message}`);
    }
  }
  if (numErrors > 0 || numWarnings > 0) failed = true;
}
process.exit(failed ? 1 : 0);

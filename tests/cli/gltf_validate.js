// SPDX-License-Identifier: Apache-2.0
// Validates glTF binary files with the Khronos glTF validator (npm package gltf-validator).
// Prints every message; exits 1 when a file has an error, 2 when the validator cannot be loaded.
// Usage: node gltf_validate.js VALIDATOR_FOLDER FILE.glb...   (the folder npm installed it into)
const fs = require('fs');
const path = require('path');

let validator;
try {
  validator = require(path.resolve(process.argv[2], 'node_modules', 'gltf-validator'));
} catch (e) {
  console.log(`gltf-validator not found under ${process.argv[2]}: tools/test.sh installs it with npm`);
  process.exit(2);
}

const severity = ['error', 'warning', 'info', 'hint'];

(async () => {
  let failed = false;
  for (const file of process.argv.slice(3)) {
    const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)));
    const issues = report.issues;
    console.log(`${file}: ${issues.numErrors} errors, ${issues.numWarnings} warnings, ` +
                `${issues.numInfos} infos, ${issues.numHints} hints (validator ${report.validatorVersion})`);
    for (const m of issues.messages) console.log(`  ${severity[m.severity]} ${m.code} ${m.pointer || ''}: ${m.message}`);
    if (issues.numErrors !== 0) failed = true;
  }
  process.exit(failed ? 1 : 0);
})().catch((e) => {
  console.log(`validator failed: ${e}`);
  process.exit(1);
});

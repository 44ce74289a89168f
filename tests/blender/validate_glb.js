// Runs the Khronos glTF validator (npm gltf-validator) on every .glb named on the command line.
// Prints one line per file (errors, warnings, infos) and every error; exits 1 if any file has
// an error. Usage: node validate_glb.js FILE.glb...
'use strict';
const fs = require('fs');
const path = require('path');
const validator = require('gltf-validator');

(async () => {
  let failed = 0;
  for (const file of process.argv.slice(2)) {
    const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)),
                                                 {uri: path.basename(file), maxIssues: 100});
    const issues = report.issues;
    console.log(`${issues.numErrors ? 'FAIL' : 'ok  '} ${path.basename(file)}: ` +
                `${issues.numErrors} errors, ${issues.numWarnings} warnings, ` +
                `${issues.numInfos} infos`);
    for (const m of issues.messages.filter((m) => m.severity === 0)) {
      console.log(`       ${m.code} ${m.pointer || ''}: ${m.message}`);
    }
    if (issues.numErrors) failed += 1;
  }
  process.exit(failed ? 1 : 0);
})().catch((error) => {
  console.error(error);
  process.exit(1);
});

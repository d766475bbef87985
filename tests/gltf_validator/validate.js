#!/usr/bin/env node
// Usage: node validate.js FILE.glb|FILE.gltf
// Prints the Khronos validator's issue counts and messages as JSON; exits 0 only when there are no
// errors, so a ctest or a gtest can assert on the exit status and show the report on failure.
'use strict';
const fs = require('fs');
const path = require('path');
const validator = require('gltf-validator');

const file = process.argv[2];
if (!file) {
  console.error('usage: validate.js FILE.glb|FILE.gltf');
  process.exit(2);
}
const dir = path.dirname(file);
let bytes;
try {
  bytes = new Uint8Array(fs.readFileSync(file));
} catch (e) {
  console.error(`${file}: ${e.message}`);
  process.exit(2);
}
validator.validateBytes(bytes, {
  uri: path.basename(file),
  maxIssues: 200,
  externalResourceFunction: (uri) => new Promise((resolve, reject) => {
    fs.readFile(path.join(dir, decodeURIComponent(uri)), (err, data) => {
      if (err) reject(err.toString()); else resolve(new Uint8Array(data));
    });
  }),
}).then((report) => {
  const issues = report.issues;
  console.log(JSON.stringify({
    errors: issues.numErrors,
    warnings: issues.numWarnings,
    infos: issues.numInfos,
    messages: issues.messages.map((m) => `${m.severity === 0 ? 'error' : 'note'} ${m.code} ${m.pointer || ''}: ${m.message}`),
    info: report.info,
  }, null, 2));
  process.exit(issues.numErrors === 0 ? 0 : 1);
}).catch((error) => {
  console.error(`${file}: validator failed: ${error}`);
  process.exit(2);
});

// Validates one glTF/GLB file with the Khronos validator and prints
// {"errors": N, "codes": {CODE: count}} (errors only) as one JSON line.
// External buffers and images are read beside the file.
const validator = require('gltf-validator');
const fs = require('fs');
const path = require('path');

const file = process.argv[2];
const bytes = new Uint8Array(fs.readFileSync(file));
const external = (uri) =>
  new Promise((resolve, reject) => {
    try {
      resolve(new Uint8Array(fs.readFileSync(path.join(path.dirname(file), decodeURIComponent(uri)))));
    } catch (e) {
      reject(String(e));
    }
  });
validator
  .validateBytes(bytes, { uri: path.basename(file), maxIssues: 10000, externalResourceFunction: external })
  .then((report) => {
    const codes = {};
    for (const m of report.issues.messages) {
      if (m.severity === 0) codes[m.code] = (codes[m.code] || 0) + 1;
    }
    console.log(JSON.stringify({ errors: report.issues.numErrors, codes }));
  })
  .catch((e) => {
    console.log(JSON.stringify({ errors: 1, codes: { FATAL: 1 }, message: String(e) }));
  });

// Reads a .usda file with TinyUSDZ (github.com/lighttransport/tinyusdz, its npm WebAssembly
// build): an implementation of USD independent of ringlet, whose parser is strict about the
// grammar (it rejects what Pixar's does not accept, e.g. a truncated time-sample block). Prints
// what TinyUSDZ read as JSON on stdout, for tests/usd/tinyusdz_test.sh to compare against other
// outputs of the same run:
//   {"stage_root_prims": N, "metadata": {name: value}, "prims": {name: {"type": T,
//    "attributes": {name: value}, "time_samples": {name: {time: [numbers]}}}}}
// Values come from TinyUSDZ's own serialization of the layer it parsed (layerToString), so every
// number is one TinyUSDZ parsed and printed back. Exit status 1 (with TinyUSDZ's error on
// stderr) when it cannot read the file as a layer or compose it as a stage.
//
//   node tests/usd/tinyusdz_read.mjs FILE.usda
import fs from 'node:fs';
import { createRequire } from 'node:module';

const require = createRequire(import.meta.url);
// The npm build targets browsers and web workers; under Node it loads as in an Electron
// renderer (process.type), given the .wasm bytes directly instead of fetching them.
process.type = 'renderer';
globalThis.window = globalThis;
const wasmPath = require.resolve('tinyusdz/tinyusdz.wasm');
const { default: initTinyUSDZ } = await import('tinyusdz/tinyusdz.js');
const native = await initTinyUSDZ({ wasmBinary: fs.readFileSync(wasmPath), locateFile: () => wasmPath });

const file = process.argv[2];
const bytes = new Uint8Array(fs.readFileSync(file));
const layer = new native.TinyUSDZLoaderNative();
if (!layer.loadAsLayerFromBinary(bytes, file)) {
  process.stderr.write(`TinyUSDZ cannot read ${file} as a layer: ${layer.error()}\n`);
  process.exit(1);
}
const stage = new native.TinyUSDZLoaderNative();
if (!stage.loadFromBinary(bytes, file)) {
  process.stderr.write(`TinyUSDZ cannot load ${file} as a stage: ${stage.error()}\n`);
  process.exit(1);
}

const numbers = (text) => (text.match(/[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?/g) || []).map(Number);
const value = (text) => {
  text = text.trim();
  if (text.startsWith('"')) return JSON.parse(text);
  if (text.startsWith('[') || text.startsWith('(')) return numbers(text);
  return Number(text);
};

// layerToString: the layer's metadata block, then `def TYPE "NAME" { ... }` with one attribute
// per line (`[uniform] TYPE NAME = VALUE`, `TYPE NAME.timeSamples = { T: VALUE, ... }`).
const text = layer.layerToString();
const out = { stage_root_prims: stage.numRootNodes(), metadata: {}, prims: {} };
const lines = text.split('\n');
let prim = null;
let samples = null;
let depth = 0;  // inside the layer's metadata parentheses
for (const line of lines) {
  const t = line.trim();
  if (prim === null && t === '(') { depth = 1; continue; }
  if (depth === 1) {
    if (t === ')') { depth = 0; continue; }
    const m = t.match(/^(\w+) = (.*)$/);
    if (m) out.metadata[m[1]] = value(m[2]);
    continue;
  }
  const def = t.match(/^def (\w+) "([^"]+)"$/);
  if (def) { prim = { type: def[1], attributes: {}, time_samples: {} }; out.prims[def[2]] = prim; continue; }
  if (prim === null) continue;
  if (samples) {
    if (t === '}') { samples = null; continue; }
    const m = t.match(/^(-?[\d.eE+-]+): (.*?),?$/);
    if (m) samples[m[1]] = value(m[2]);
    continue;
  }
  const ts = t.match(/^(?:uniform )?\S+ ([\w:]+)\.timeSamples = \{$/);
  if (ts) { samples = {}; prim.time_samples[ts[1]] = samples; continue; }
  const attr = t.match(/^(?:uniform )?\S+ ([\w:]+) = (.*?)( \($)?$/);
  if (attr) prim.attributes[attr[1]] = value(attr[2]);
}
process.stdout.write(JSON.stringify(out) + '\n');

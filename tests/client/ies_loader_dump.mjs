// Loads an IES file with three.js's IESLoader (its parse(), under plain
// node) and writes the texture it makes as JSON: {rows, columns, values},
// values[row * columns + column] with row = horizontal angle (0…359°, or a
// single row for rotational symmetry) and column k = vertical angle
// k·180/179°, normalised by the loader to the file's peak.
//
//   node ies_loader_dump.mjs THREE_DIR FILE.ies OUT.json
import { readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';

const [threeDir, iesPath, outPath] = process.argv.slice(2);
if (!outPath) {
  console.error('usage: node ies_loader_dump.mjs THREE_DIR FILE.ies OUT.json');
  process.exit(2);
}
const three = await import(pathToFileURL(join(threeDir, 'build', 'three.module.js')));
const { IESLoader } = await import(pathToFileURL(join(threeDir, 'examples', 'jsm', 'loaders', 'IESLoader.js')));
const loader = new IESLoader();
loader.type = three.FloatType;  // the default half floats would round to 1e-3
const texture = loader.parse(readFileSync(iesPath, 'latin1'));
const { width, height, data } = texture.image;
writeFileSync(outPath, JSON.stringify({ rows: height, columns: width, values: Array.from(data) }));

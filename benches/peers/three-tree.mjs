// The three.js tree generator (examples/jsm/generators/TreeGenerator.js in the `three`
// package) in Node: median time of build() at 4 and 5 levels, with the triangles it makes
// (run by run.sh; prints one table row per size). A plain material is passed so that no
// shader graph is built: only the skeleton and the geometry are timed.
import { MeshBasicMaterial } from 'three';
import { TreeGenerator } from 'three/examples/jsm/generators/TreeGenerator.js';

const material = new MeshBasicMaterial();
for (const levels of [4, 5]) {
  const times = [];
  let triangles = 0, vertices = 0, indexType = '';
  for (let k = 0; k < 25; k++) {
    const generator = new TreeGenerator(material).setSeed(1).setLevels(levels);
    const start = process.hrtime.bigint();
    const mesh = generator.build();
    times.push(Number(process.hrtime.bigint() - start) / 1e9);
    triangles = mesh.geometry.index.count / 3;
    vertices = mesh.geometry.attributes.position.count;
    indexType = mesh.geometry.index.array.constructor.name;
  }
  times.sort((a, b) => a - b);
  const median = times[times.length >> 1];
  console.log(`| three.js TreeGenerator, ${levels} levels | ${triangles} | ${vertices} (${indexType} indices) | ${(triangles / median / 1e6).toFixed(2)} |`);
}

// @dgreenheck/ez-tree in Node: median time of Tree.generate() for its default tree, and
// the bark triangles it makes (run by run.sh; prints one table row).
const el = () => ({ addEventListener() {}, removeEventListener() {}, setAttribute() {}, style: {} });
// three.js queues ez-tree's bark textures through the DOM; geometry does not need them.
globalThis.document = { createElementNS: el, createElement: el };
const { Tree } = await import('@dgreenheck/ez-tree');
const times = [];
let triangles = 0, vertices = 0, indexType = '';
for (let k = 0; k < 15; k++) {
  const t = new Tree();
  t.options.seed = 1;
  const start = process.hrtime.bigint();
  t.generate();
  times.push(Number(process.hrtime.bigint() - start) / 1e9);
  const bark = t.children[0].geometry;
  triangles = bark.index.count / 3;
  vertices = bark.attributes.position.count;
  indexType = bark.index.array.constructor.name;
}
times.sort((a, b) => a - b);
const median = times[times.length >> 1];
console.log(`| ez-tree default tree | ${triangles} | ${vertices} (${indexType} indices) | ${(triangles / median / 1e6).toFixed(2)} |`);

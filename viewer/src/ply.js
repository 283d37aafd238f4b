// A binary little-endian PLY reader (the format terramesh writes: docs/formats.md). Returns each
// element's scalar properties as typed arrays and list properties as flat values plus offsets.

const TYPES = {
  char: ['getInt8', 1, Int8Array], int8: ['getInt8', 1, Int8Array],
  uchar: ['getUint8', 1, Uint8Array], uint8: ['getUint8', 1, Uint8Array],
  short: ['getInt16', 2, Int16Array], int16: ['getInt16', 2, Int16Array],
  ushort: ['getUint16', 2, Uint16Array], uint16: ['getUint16', 2, Uint16Array],
  int: ['getInt32', 4, Int32Array], int32: ['getInt32', 4, Int32Array],
  uint: ['getUint32', 4, Uint32Array], uint32: ['getUint32', 4, Uint32Array],
  float: ['getFloat32', 4, Float32Array], float32: ['getFloat32', 4, Float32Array],
  double: ['getFloat64', 8, Float64Array], float64: ['getFloat64', 8, Float64Array],
};

function typeOf(name, line) {
  const type = TYPES[name];
  if (!type) throw new Error(`PLY header: unknown type "${name}" in "${line}"`);
  return type;
}

/** Parses the header; returns {elements, comments, dataOffset}. */
export function parsePlyHeader(buffer) {
  const bytes = new Uint8Array(buffer);
  const limit = Math.min(bytes.length, 1 << 16);
  let text = '';
  for (let i = 0; i < limit; ++i) text += String.fromCharCode(bytes[i]);
  const end = text.indexOf('end_header');
  if (!text.startsWith('ply') || end < 0) throw new Error('not a PLY file (no "ply" ... "end_header")');
  let dataOffset = end + 'end_header'.length;
  if (text[dataOffset] === '\r') ++dataOffset;
  ++dataOffset;  // the newline
  const elements = [];
  const comments = [];
  for (const raw of text.slice(0, end).split('\n')) {
    const line = raw.trim();
    const words = line.split(/\s+/);
    if (words[0] === 'format' && words[1] !== 'binary_little_endian') {
      throw new Error(`PLY format "${words[1]}" not supported (expected binary_little_endian)`);
    } else if (words[0] === 'comment') {
      comments.push(line.slice(8));
    } else if (words[0] === 'element') {
      elements.push({ name: words[1], count: Number(words[2]), properties: [] });
    } else if (words[0] === 'property') {
      const element = elements[elements.length - 1];
      if (!element) throw new Error(`PLY header: property before any element: "${line}"`);
      if (words[1] === 'list') {
        element.properties.push({ name: words[4], list: true, countType: typeOf(words[2], line), type: typeOf(words[3], line) });
      } else {
        element.properties.push({ name: words[2], list: false, type: typeOf(words[1], line) });
      }
    }
  }
  return { elements, comments, dataOffset };
}

/**
 * Parses a whole binary little-endian PLY. Each element gets `scalars` {name: TypedArray} and
 * `lists` {name: {values: TypedArray, offsets: Uint32Array}}.
 */
export function parsePly(buffer) {
  const { elements, comments, dataOffset } = parsePlyHeader(buffer);
  const view = new DataView(buffer);
  let offset = dataOffset;
  for (const element of elements) {
    element.scalars = {};
    element.lists = {};
    const n = element.count;
    const hasList = element.properties.some((p) => p.list);
    for (const p of element.properties) {
      if (!p.list) element.scalars[p.name] = new p.type[2](n);
    }
    if (!hasList) {
      // Fixed stride: read column by column.
      let stride = 0;
      const columns = element.properties.map((p) => { const at = stride; stride += p.type[1]; return at; });
      if (offset + stride * n > buffer.byteLength) throw new Error(`PLY: element ${element.name} is truncated`);
      element.properties.forEach((p, k) => {
        const out = element.scalars[p.name];
        const get = view[p.type[0]].bind(view);
        for (let i = 0, at = offset + columns[k]; i < n; ++i, at += stride) out[i] = get(at, true);
      });
      offset += stride * n;
      continue;
    }
    const lists = element.properties.filter((p) => p.list).map((p) => ({
      p, values: [], offsets: new Uint32Array(n + 1) }));
    const listOf = Object.fromEntries(lists.map((l) => [l.p.name, l]));
    const readers = element.properties.map((p) => ({ p, get: view[p.type[0]].bind(view),
      getCount: p.list ? view[p.countType[0]].bind(view) : null }));
    for (let i = 0; i < n; ++i) {
      for (const { p, get, getCount } of readers) {
        if (p.list) {
          const count = getCount(offset, true);
          offset += p.countType[1];
          const list = listOf[p.name];
          for (let c = 0; c < count; ++c, offset += p.type[1]) list.values.push(get(offset, true));
          list.offsets[i + 1] = list.values.length;
        } else {
          element.scalars[p.name][i] = get(offset, true);
          offset += p.type[1];
        }
      }
      if (offset > buffer.byteLength) throw new Error(`PLY: element ${element.name} is truncated`);
    }
    for (const list of lists) {
      element.lists[list.p.name] = { values: new list.p.type[2](list.values), offsets: list.offsets };
    }
  }
  return { elements, comments, element: (name) => elements.find((e) => e.name === name) };
}

// Small parsers for the run's text files: CSV with a header, and map_frame.yaml's flat keys.

/** Parses CSV with a header row into {header, columns: {name: number[] | string[]}, rows}. */
export function parseCsv(text) {
  const lines = text.split(/\r?\n/).filter((l) => l.length > 0 && !l.startsWith('#'));
  if (lines.length === 0) return { header: [], columns: {}, rows: 0 };
  const header = lines[0].split(',').map((h) => h.trim());
  const columns = Object.fromEntries(header.map((h) => [h, []]));
  for (let r = 1; r < lines.length; ++r) {
    const cells = lines[r].split(',');
    header.forEach((h, k) => {
      const cell = (cells[k] ?? '').trim();
      const number = Number(cell);
      columns[h].push(cell !== '' && Number.isFinite(number) ? number : cell);
    });
  }
  return { header, columns, rows: lines.length - 1 };
}

/** Reads `key: value` and `key: [a, b, c]` lines (map_frame.yaml); comments ignored. */
export function parseFlatYaml(text) {
  const out = {};
  for (const raw of text.split(/\r?\n/)) {
    const line = raw.replace(/#.*$/, '').trim();
    const colon = line.indexOf(':');
    if (colon <= 0) continue;
    const key = line.slice(0, colon).trim();
    const value = line.slice(colon + 1).trim();
    if (value.startsWith('[')) {
      out[key] = value.replace(/[[\]]/g, '').split(',').map(Number);
    } else {
      const number = Number(value);
      out[key] = value !== '' && Number.isFinite(number) ? number : value;
    }
  }
  return out;
}

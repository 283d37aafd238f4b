// A minimal PNG decoder (8-bit RGB/RGBA, not interlaced: what Chromium's screenshots are), so
// the tests read pixels without another npm package.
import { inflateSync } from 'node:zlib';

export function decodePng(buffer) {
  const signature = '89504e470d0a1a0a';
  if (buffer.subarray(0, 8).toString('hex') !== signature) throw new Error('not a PNG');
  let offset = 8;
  let width = 0, height = 0, colourType = 0, bitDepth = 0, interlace = 0;
  const data = [];
  while (offset < buffer.length) {
    const length = buffer.readUInt32BE(offset);
    const type = buffer.toString('ascii', offset + 4, offset + 8);
    const body = buffer.subarray(offset + 8, offset + 8 + length);
    if (type === 'IHDR') {
      width = body.readUInt32BE(0); height = body.readUInt32BE(4);
      bitDepth = body[8]; colourType = body[9]; interlace = body[12];
    } else if (type === 'IDAT') {
      data.push(body);
    } else if (type === 'IEND') {
      break;
    }
    offset += 12 + length;
  }
  if (bitDepth !== 8 || interlace !== 0 || (colourType !== 2 && colourType !== 6)) {
    throw new Error(`PNG: unsupported depth ${bitDepth}, colour type ${colourType}, interlace ${interlace}`);
  }
  const channels = colourType === 6 ? 4 : 3;
  const raw = inflateSync(Buffer.concat(data));
  const stride = width * channels;
  const rgba = new Uint8Array(width * height * 4);
  const previous = new Uint8Array(stride);
  const line = new Uint8Array(stride);
  for (let y = 0; y < height; ++y) {
    const filter = raw[y * (stride + 1)];
    const row = raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1));
    for (let i = 0; i < stride; ++i) {
      const a = i >= channels ? line[i - channels] : 0;
      const b = previous[i];
      const c = i >= channels ? previous[i - channels] : 0;
      let value = row[i];
      if (filter === 1) value += a;
      else if (filter === 2) value += b;
      else if (filter === 3) value += (a + b) >> 1;
      else if (filter === 4) {
        const p = a + b - c, pa = Math.abs(p - a), pb = Math.abs(p - b), pc = Math.abs(p - c);
        value += pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      }
      line[i] = value & 0xff;
    }
    for (let x = 0; x < width; ++x) {
      for (let k = 0; k < 3; ++k) rgba[4 * (y * width + x) + k] = line[x * channels + k];
      rgba[4 * (y * width + x) + 3] = channels === 4 ? line[x * channels + 3] : 255;
    }
    previous.set(line);
  }
  return { width, height, rgba };
}

/** Fraction of pixels whose RGB differs from `rgb` by more than `tolerance` in any channel. */
export function fractionNot(image, rgb, tolerance = 6) {
  let count = 0;
  const n = image.width * image.height;
  for (let i = 0; i < n; ++i) {
    const p = 4 * i;
    if (Math.abs(image.rgba[p] - rgb[0]) > tolerance || Math.abs(image.rgba[p + 1] - rgb[1]) > tolerance ||
        Math.abs(image.rgba[p + 2] - rgb[2]) > tolerance) ++count;
  }
  return count / n;
}

/** Fraction of pixels that differ between two images of the same size. */
export function fractionChanged(a, b, tolerance = 6) {
  if (a.width !== b.width || a.height !== b.height) return 1;
  let count = 0;
  for (let i = 0; i < a.width * a.height; ++i) {
    const p = 4 * i;
    if (Math.abs(a.rgba[p] - b.rgba[p]) > tolerance || Math.abs(a.rgba[p + 1] - b.rgba[p + 1]) > tolerance ||
        Math.abs(a.rgba[p + 2] - b.rgba[p + 2]) > tolerance) ++count;
  }
  return count / (a.width * a.height);
}

/** Number of pixels within `tolerance` of `rgb`. */
export function countColour(image, rgb, tolerance = 40) {
  let count = 0;
  for (let i = 0; i < image.width * image.height; ++i) {
    const p = 4 * i;
    if (Math.abs(image.rgba[p] - rgb[0]) <= tolerance && Math.abs(image.rgba[p + 1] - rgb[1]) <= tolerance &&
        Math.abs(image.rgba[p + 2] - rgb[2]) <= tolerance) ++count;
  }
  return count;
}

// Reads a LAS 1.4 file with copc.js (an independent reader from the npm registry, MIT) and
// prints what it found as JSON: the header, the VLRs, the Extra Bytes descriptors, the WKT
// and every point's coordinates, GPS time and extra-bytes values, each by its name.
// Usage: node read_las_with_copc.js FILE.las
'use strict';
const fs = require('fs');
const { Las } = require('copc');

const bytes = new Uint8Array(fs.readFileSync(process.argv[2]));
const header = Las.Header.parse(bytes.subarray(0, 375));
const getter = async (begin, end) => bytes.subarray(begin, end);

(async () => {
  const vlrs = await Las.Vlr.walk(getter, header);
  const content = (vlr) => bytes.subarray(vlr.contentOffset, vlr.contentOffset + vlr.contentLength);
  const ebVlr = Las.Vlr.find(vlrs, 'LASF_Spec', 4);
  const eb = ebVlr ? Las.ExtraBytes.parse(content(ebVlr)) : [];
  const wktVlr = Las.Vlr.find(vlrs, 'LASF_Projection', 2112);
  const wkt = wktVlr ? Buffer.from(content(wktVlr)).toString('latin1').replace(/\0+$/, '') : null;
  const records = bytes.subarray(header.pointDataOffset,
    header.pointDataOffset + header.pointCount * header.pointDataRecordLength);
  const view = Las.View.create(records, header, eb);
  const names = ['X', 'Y', 'Z', 'GpsTime', 'ReturnNumber', 'NumberOfReturns', ...eb.map((e) => e.name)];
  const points = {};
  for (const name of names) {
    const get = view.getter(name);
    points[name] = Array.from({ length: view.pointCount }, (_, i) => get(i));
  }
  process.stdout.write(JSON.stringify({
    version: `${header.majorVersion}.${header.minorVersion}`,
    format: header.pointDataRecordFormat,
    recordLength: header.pointDataRecordLength,
    pointCount: header.pointCount,
    globalEncoding: header.globalEncoding,
    scale: header.scale,
    offset: header.offset,
    min: header.min,
    max: header.max,
    vlrs: vlrs.map((v) => ({ user: v.userId, record: v.recordId })),
    extraBytes: eb.map((e) => ({ name: e.name, type: e.type, length: e.length, min: e.min, max: e.max })),
    wkt,
    points,
  }, (k, v) => (typeof v === 'number' && !Number.isFinite(v) ? String(v) : v)));
})().catch((e) => { console.error(e.stack || String(e)); process.exit(1); });

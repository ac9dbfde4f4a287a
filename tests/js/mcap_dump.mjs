#!/usr/bin/env node
// Usage: node mcap_dump.mjs FILE.mcap
//
// Reads an MCAP file with @mcap/core (Foxglove's TypeScript MCAP library, independent of our
// C++ reader) twice: with McapIndexedReader (footer -> summary -> chunk indexes -> message
// indexes) and with McapStreamReader (every record from the start, chunk CRCs checked). Fails
// (exit 1, reason on stderr) unless both see the same header, schemas, channels and messages.
// Prints JSON: profile, library, schemas, channels, statistics and, per message in log-time
// order, channel, sequence, times and the sha256 of its data. uint64 values (times, counts) are
// printed as decimal strings because JSON numbers cannot hold them exactly.
// Only uncompressed chunks are supported (no zstd/lz4 decompressor is installed).
import { open } from "node:fs/promises";

import { McapIndexedReader, McapStreamReader } from "@mcap/core";
import { FileReadable, sha256 } from "./file_readable.mjs";

function fail(message) {
  process.stderr.write(`mcap_dump: ${message}\n`);
  process.exit(1);
}


const describeSchema = (s) => ({
  id: s.id,
  name: s.name,
  encoding: s.encoding,
  dataLength: s.data.byteLength,
  dataSha256: sha256(s.data),
});
const describeChannel = (c) => ({
  id: c.id,
  topic: c.topic,
  messageEncoding: c.messageEncoding,
  schemaId: c.schemaId,
  metadata: Object.fromEntries([...c.metadata.entries()].sort()),
});
const describeMessage = (m) => ({
  channelId: m.channelId,
  sequence: m.sequence,
  logTime: m.logTime.toString(),
  publishTime: m.publishTime.toString(),
  dataLength: m.data.byteLength,
  sha256: sha256(m.data),
});
const describeStatistics = (s) =>
  s && {
    messageCount: s.messageCount.toString(),
    schemaCount: s.schemaCount,
    channelCount: s.channelCount,
    chunkCount: s.chunkCount,
    messageStartTime: s.messageStartTime.toString(),
    messageEndTime: s.messageEndTime.toString(),
    channelMessageCounts: Object.fromEntries(
      [...s.channelMessageCounts.entries()].map(([id, n]) => [String(id), n.toString()]),
    ),
  };
const byId = (map, describe) => [...map.values()].sort((a, b) => a.id - b.id).map(describe);

async function readIndexed(handle) {
  const reader = await McapIndexedReader.Initialize({ readable: new FileReadable(handle) });
  const messages = [];
  for await (const m of reader.readMessages()) messages.push(describeMessage(m));
  return {
    profile: reader.header.profile,
    library: reader.header.library,
    schemas: byId(reader.schemasById, describeSchema),
    channels: byId(reader.channelsById, describeChannel),
    statistics: describeStatistics(reader.statistics),
    messages,
  };
}

async function readStreamed(handle) {
  const reader = new McapStreamReader({ validateCrcs: true });
  let header;
  let statistics;
  const schemas = new Map();
  const channels = new Map();
  const messages = [];
  const block = new Uint8Array(1 << 20);
  for (let position = 0; ; ) {
    const { bytesRead } = await handle.read(block, 0, block.length, position);
    if (bytesRead === 0) break;
    position += bytesRead;
    reader.append(block.subarray(0, bytesRead));
    for (let record; (record = reader.nextRecord()); ) {
      if (record.type === "Header") header = record;
      else if (record.type === "Schema") schemas.set(record.id, record);
      else if (record.type === "Channel") channels.set(record.id, record);
      else if (record.type === "Statistics") statistics = record;
      else if (record.type === "Message") messages.push(describeMessage(record));
    }
  }
  if (!reader.done()) fail("McapStreamReader did not reach the footer and closing magic");
  return {
    profile: header?.profile,
    library: header?.library,
    schemas: byId(schemas, describeSchema),
    channels: byId(channels, describeChannel),
    statistics: describeStatistics(statistics),
    messages,
  };
}

// Ties in log time may come in either order from the two readers; compare in one fixed order.
function canonical(messages) {
  const key = (m) => [BigInt(m.logTime), m.channelId, m.sequence, m.sha256];
  return [...messages].sort((a, b) => {
    const ka = key(a);
    const kb = key(b);
    for (let i = 0; i < ka.length; ++i) if (ka[i] !== kb[i]) return ka[i] < kb[i] ? -1 : 1;
    return 0;
  });
}

function expectSame(what, a, b) {
  const ja = JSON.stringify(a);
  const jb = JSON.stringify(b);
  if (ja !== jb) fail(`indexed and streaming readers disagree on ${what}:\n  ${ja}\n  ${jb}`);
}

async function main() {
  const path = process.argv[2];
  if (!path) fail("usage: node mcap_dump.mjs FILE.mcap");
  const handle = await open(path, "r");
  try {
    const indexed = await readIndexed(handle);
    const streamed = await readStreamed(handle);
    for (const field of ["profile", "library", "schemas", "channels", "statistics"]) {
      expectSame(field, indexed[field], streamed[field]);
    }
    expectSame("messages", canonical(indexed.messages), canonical(streamed.messages));
    process.stdout.write(`${JSON.stringify(indexed, null, 2)}\n`);
  } finally {
    await handle.close();
  }
}

main().catch((e) => fail(e?.stack ?? String(e)));

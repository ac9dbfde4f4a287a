#!/usr/bin/env node
// Usage: node foxglove_decode.mjs FILE.mcap [--max N]
//
// Decodes an MCAP recording the way Foxglove Studio does for `cdr` messages with an `omgidl`
// schema (parseChannel in @foxglove/mcap-support / Lichtblick's fork): parseIDL(schema text) from
// @foxglove/omgidl-parser, then new MessageReader(schema name, definitions) from
// @foxglove/omgidl-serialization, then reader.readMessage(message data). Nothing of ours is used.
// Every message (or the first N of each channel) is decoded and then re-encoded with
// MessageWriter; the bytes must be identical, which proves the decoder consumed exactly the
// message and read every field at the right offset.
// Prints JSON: per channel its topic, schema, message counts and, per decoded message, the header
// (uint64 as decimal strings) and, for df::msg::RgbdFrame, image size, intrinsics and sha256 of
// the used part of rgb (width*height*3 bytes) and depth (width*height uint16, little endian).
// Fails (exit 1, reason on stderr) on any schema that Foxglove would reject or any decode error.
import { open } from "node:fs/promises";

import { parseIDL } from "@foxglove/omgidl-parser";
import { MessageReader, MessageWriter } from "@foxglove/omgidl-serialization";
import { McapIndexedReader } from "@mcap/core";
import { FileReadable, sha256 } from "./file_readable.mjs";

function fail(message) {
  // nearley syntax errors go on to list every expected token; the first lines say what is wrong
  message = String(message).split(" Instead, I was expecting")[0];
  process.stderr.write(`foxglove_decode: ${message}\n`);
  process.exit(1);
}


/** Foxglove's parseChannel, `cdr` + `omgidl` branch, plus a writer for the round-trip check. */
function parseChannel(channel, schema) {
  const where = `channel ${channel.id} (${channel.topic})`;
  if (channel.messageEncoding !== "cdr") {
    fail(`${where}: message encoding "${channel.messageEncoding}", expected "cdr"`);
  }
  if (schema?.encoding !== "omgidl") {
    fail(`${where}: schema encoding "${schema?.encoding}", expected "omgidl"`);
  }
  try {
    const definitions = parseIDL(new TextDecoder().decode(schema.data));
    return {
      reader: new MessageReader(schema.name, definitions),
      writer: new MessageWriter(schema.name, definitions, { kind: 1 /* CDR_LE */ }),
    };
  } catch (e) {
    return fail(`${where}: Foxglove cannot parse schema "${schema.name}": ${e?.message ?? e}`);
  }
}

const describeHeader = (h) => ({
  capture_ns: h.capture_ns.toString(),
  sensor_ns: h.sensor_ns.toString(),
  seq: h.seq.toString(),
  source_id: h.source_id,
  status: h.status,
});

function describeFrame(m) {
  const pixels = m.width * m.height;
  const depth = m.depth.subarray(0, pixels);
  const depthLe = Buffer.alloc(pixels * 2);
  depth.forEach((v, i) => depthLe.writeUInt16LE(v, i * 2));
  return {
    width: m.width,
    height: m.height,
    intrinsics: m.intrinsics,
    depth_units_per_m: m.depth_units_per_m,
    rgbLength: m.rgb.length,
    rgbSha256: sha256(m.rgb.subarray(0, pixels * 3)),
    depthLength: m.depth.length,
    depthSha256: sha256(depthLe),
  };
}

async function main() {
  const args = process.argv.slice(2);
  const maxAt = args.indexOf("--max");
  const max = maxAt >= 0 ? Number(args.splice(maxAt, 2)[1]) : Infinity;
  if (args.length !== 1 || !(max >= 0)) fail("usage: node foxglove_decode.mjs FILE.mcap [--max N]");
  const handle = await open(args[0], "r");
  try {
    const mcap = await McapIndexedReader.Initialize({ readable: new FileReadable(handle) });
    const channels = new Map();
    for (const channel of [...mcap.channelsById.values()].sort((a, b) => a.id - b.id)) {
      const schema = mcap.schemasById.get(channel.schemaId);
      const out = { topic: channel.topic, schema: schema?.name, messages: 0, decoded: 0 };
      out.decodedMessages = [];
      channels.set(channel.id, { ...parseChannel(channel, schema), out });
    }
    for await (const m of mcap.readMessages()) {
      const c = channels.get(m.channelId);
      if (!c) fail(`message on unknown channel ${m.channelId}`);
      if (c.out.messages++ >= max) continue;
      const where = `${c.out.topic} message ${m.sequence} (log time ${m.logTime})`;
      let decoded;
      let reencoded;
      try {
        decoded = c.reader.readMessage(m.data);
        reencoded = c.writer.writeMessage(decoded);
      } catch (e) {
        fail(`${where}: Foxglove cannot decode it as ${c.out.schema}: ${e?.message ?? e}`);
      }
      if (Buffer.compare(reencoded, m.data) !== 0) {
        fail(
          `${where}: re-encoding the decoded message gives ${reencoded.length} bytes that differ ` +
            `from the recorded ${m.data.length} bytes (schema does not match the recorded layout?)`,
        );
      }
      const out = { header: describeHeader(decoded.header) };
      if (c.out.schema === "df::msg::RgbdFrame") Object.assign(out, describeFrame(decoded));
      c.out.decoded++;
      c.out.decodedMessages.push(out);
    }
    const result = { channels: [...channels.values()].map((c) => c.out) };
    process.stdout.write(`${JSON.stringify(result, null, 2)}\n`);
  } finally {
    await handle.close();
  }
}

main().catch((e) => fail(e?.stack ?? String(e)));

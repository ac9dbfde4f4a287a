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
// the used part of rgb (width*height*3 bytes) and depth (width*height uint16, little endian); for
// camera poses, detections and object poses their values; for Foxglove's own schemas (foxglove::*,
// written by df_tap record --foxglove) the fields Studio's panels read, image data as sha256.
// Fails (exit 1, reason on stderr) on any schema that Foxglove would reject or any decode error.
import { open } from "node:fs/promises";

import { parseIDL } from "@foxglove/omgidl-parser";
import { MessageReader, MessageWriter } from "@foxglove/omgidl-serialization";
import { McapIndexedReader } from "@mcap/core";
import { decompress } from "fzstd";
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

const time = (t) => ({ sec: t.sec, nsec: t.nsec });
const describeRgba = (c) => [c.r, c.g, c.b, c.a];

/** Foxglove's own schemas (df_tap record --foxglove): what Studio's panels read of them. */
const describeFoxglove = {
  "foxglove::RawImage": (m) => ({
    timestamp: time(m.timestamp),
    frame_id: m.frame_id,
    width: m.width,
    height: m.height,
    encoding: m.encoding,
    step: m.step,
    dataLength: m.data.length,
    dataSha256: sha256(m.data),
  }),
  "foxglove::CompressedImage": (m) => ({
    timestamp: time(m.timestamp),
    frame_id: m.frame_id,
    format: m.format,
    dataLength: m.data.length,
    dataSha256: sha256(m.data),
  }),
  "foxglove::ImageAnnotations": (m) => ({
    points: m.points.map((p) => ({
      timestamp: time(p.timestamp),
      type: p.type,
      points: p.points.map((q) => [q.x, q.y]),
      outline_color: describeRgba(p.outline_color),
      thickness: p.thickness,
    })),
    texts: m.texts.map((t) => ({ text: t.text, position: [t.position.x, t.position.y] })),
  }),
  "foxglove::FrameTransform": (m) => ({
    timestamp: time(m.timestamp),
    parent_frame_id: m.parent_frame_id,
    child_frame_id: m.child_frame_id,
    translation: [m.translation.x, m.translation.y, m.translation.z],
    rotation: [m.rotation.x, m.rotation.y, m.rotation.z, m.rotation.w],
  }),
  "foxglove::PointCloud": (m) => ({
    timestamp: time(m.timestamp),
    frame_id: m.frame_id,
    point_stride: m.point_stride,
    fields: m.fields.map((f) => ({ name: f.name, offset: f.offset, type: f.type })),
    dataLength: m.data.length,
    dataSha256: sha256(m.data),
  }),
  "foxglove::SceneUpdate": (m) => ({
    deletions: m.deletions.map((d) => ({ type: d.type, id: d.id })),
    entities: m.entities.map((e) => ({
      id: e.id,
      frame_id: e.frame_id,
      frame_locked: e.frame_locked,
      cubes: e.cubes.map((c) => ({
        position: [c.pose.position.x, c.pose.position.y, c.pose.position.z],
        size: [c.size.x, c.size.y, c.size.z],
      })),
      lines: e.lines.map((l) => ({ type: l.type, points: l.points.length })),
      texts: e.texts.map((t) => t.text),
    })),
  }),
};

const describePose = (p) => ({ t: [p.tx, p.ty, p.tz], q: [p.qx, p.qy, p.qz, p.qw] });

async function main() {
  const args = process.argv.slice(2);
  const maxAt = args.indexOf("--max");
  const max = maxAt >= 0 ? Number(args.splice(maxAt, 2)[1]) : Infinity;
  if (args.length !== 1 || !(max >= 0)) fail("usage: node foxglove_decode.mjs FILE.mcap [--max N]");
  const handle = await open(args[0], "r");
  try {
    // zstd chunks (df_slam offline --foxglove, df_tap record --zstd) through fzstd, as Studio
    // decompresses them.
    const mcap = await McapIndexedReader.Initialize({
      readable: new FileReadable(handle),
      decompressHandlers: { zstd: (data, size) => decompress(data, new Uint8Array(Number(size))) },
    });
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
      const out = decoded.header ? { header: describeHeader(decoded.header) } : {};
      out.sequence = m.sequence;
      if (c.out.schema === "df::msg::RgbdFrame") Object.assign(out, describeFrame(decoded));
      if (c.out.schema === "df::msg::CameraPose") {
        Object.assign(out, { state: decoded.state, world_T_camera: describePose(decoded.world_T_camera) });
      }
      if (c.out.schema === "df::msg::Detections") {
        out.boxes = [...decoded.boxes].slice(0, decoded.count).map((b) => [b.x, b.y, b.w, b.h, b.class_id]);
        out.image_width = decoded.image_width;
      }
      if (c.out.schema === "df::msg::ObjectPoses") {
        out.objects = [...decoded.objects].slice(0, decoded.count).map((o) => ({
          object_id: o.object_id,
          world_T_object: describePose(o.world_T_object),
        }));
      }
      if (c.out.schema === "df::msg::MapCloud") {
        const pts = [...decoded.points].slice(0, decoded.point_count);
        out.point_count = decoded.point_count;
        out.first_points = pts.slice(0, 3).map((p) => [p.x, p.y, p.z, p.r, p.g, p.b]);
        out.objects = [...decoded.objects].slice(0, decoded.object_count).map((o) => o.object_id);
      }
      if (c.out.schema === "foxglove::PointCloud") {
        const view = new DataView(decoded.data.buffer, decoded.data.byteOffset, decoded.data.byteLength);
        out.first_points = [];
        for (let i = 0; i < Math.min(3, decoded.data.length / decoded.point_stride); ++i) {
          const o = i * decoded.point_stride;
          out.first_points.push([view.getFloat32(o, true), view.getFloat32(o + 4, true),
            view.getFloat32(o + 8, true), decoded.data[o + 12], decoded.data[o + 13], decoded.data[o + 14]]);
        }
      }
      if (c.out.schema in describeFoxglove) Object.assign(out, describeFoxglove[c.out.schema](decoded));
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

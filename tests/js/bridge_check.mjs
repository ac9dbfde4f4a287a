#!/usr/bin/env node
// Usage: node bridge_check.mjs ws://HOST:PORT PREFIX --images N --transforms N [--timeout-ms T]
//
// Connects to `df_tap bridge` the way Foxglove Studio does (FoxgloveClient of
// @foxglove/ws-protocol over the `ws` package, subprotocol foxglove.websocket.v1; nothing of
// ours), subscribes to PREFIX/color and PREFIX/tf, decodes each message with the schema the
// channel advertised (@foxglove/omgidl-parser + MessageReader, as Studio does for cdr/omgidl),
// and prints, once it has N images and N transforms, a JSON summary: per image its timestamp,
// size, encoding and sha256 of the pixels; per transform its frames, timestamp and values.
// Prints "subscribed" on stderr once both subscriptions are made. Exits 1 with the reason on
// stderr on a bad schema, a decoding error or a timeout.
import { createHash } from "node:crypto";

import pkg from "@foxglove/ws-protocol";
import { parseIDL } from "@foxglove/omgidl-parser";
import { MessageReader } from "@foxglove/omgidl-serialization";
import WebSocket from "ws";

const { FoxgloveClient } = pkg;
const args = process.argv.slice(2);
const opt = (name, fallback) => {
  const i = args.indexOf(name);
  return i >= 0 ? Number(args[i + 1]) : fallback;
};
const [url, prefix] = args;
const wantImages = opt("--images", 5);
const wantTransforms = opt("--transforms", 5);
const timeoutMs = opt("--timeout-ms", 60000);
const fail = (m) => {
  process.stderr.write(`bridge_check: ${m}\n`);
  process.exit(1);
};
if (!url || !prefix) fail("usage: node bridge_check.mjs ws://HOST:PORT PREFIX [--images N] [--transforms N]");

const ws = new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
const client = new FoxgloveClient({ ws });
const subs = new Map(); // subscription id -> { kind, reader, schemaName }
const out = { channels: {}, images: [], transforms: [] };
const timer = setTimeout(() => fail(`timed out: ${out.images.length} images, ${out.transforms.length} transforms`), timeoutMs);

client.on("error", (e) => fail(`client error: ${e?.message ?? e}`));
client.on("advertise", (channels) => {
  for (const c of channels) {
    const kind = c.topic === `${prefix}/color` ? "image" : c.topic === `${prefix}/tf` ? "tf" : null;
    if (!kind || [...subs.values()].some((s) => s.kind === kind)) continue;
    if (c.encoding !== "cdr" || c.schemaEncoding !== "omgidl") fail(`${c.topic}: ${c.encoding}/${c.schemaEncoding}`);
    let reader;
    try {
      reader = new MessageReader(c.schemaName, parseIDL(c.schema));
    } catch (e) {
      fail(`${c.topic}: Foxglove cannot parse schema ${c.schemaName}: ${e?.message ?? e}`);
    }
    out.channels[kind] = { topic: c.topic, schemaName: c.schemaName };
    subs.set(client.subscribe(c.id), { kind, reader, schemaName: c.schemaName });
    if (subs.size === 2) process.stderr.write("subscribed\n");
  }
});
const stamp = (t) => (BigInt(t.sec) * 1000000000n + BigInt(t.nsec)).toString();
client.on("message", ({ subscriptionId, data }) => {
  const s = subs.get(subscriptionId);
  if (!s) fail(`message for unknown subscription ${subscriptionId}`);
  let m;
  try {
    m = s.reader.readMessage(new Uint8Array(data.buffer, data.byteOffset, data.byteLength));
  } catch (e) {
    fail(`cannot decode a ${s.schemaName}: ${e?.message ?? e}`);
  }
  if (s.kind === "image" && out.images.length < wantImages) {
    out.images.push({
      stamp: stamp(m.timestamp), width: m.width, height: m.height, encoding: m.encoding ?? m.format,
      step: m.step, sha256: createHash("sha256").update(m.data).digest("hex"),
    });
  }
  if (s.kind === "tf" && out.transforms.length < wantTransforms) {
    out.transforms.push({
      stamp: stamp(m.timestamp), parent: m.parent_frame_id, child: m.child_frame_id,
      t: [m.translation.x, m.translation.y, m.translation.z],
      q: [m.rotation.x, m.rotation.y, m.rotation.z, m.rotation.w],
    });
  }
  if (out.images.length >= wantImages && out.transforms.length >= wantTransforms) {
    clearTimeout(timer);
    process.stdout.write(`${JSON.stringify(out)}\n`);
    client.close();
    process.exit(0);
  }
});

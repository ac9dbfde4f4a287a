#!/usr/bin/env node
// Usage: node ws_client_check.mjs ws://127.0.0.1:PORT [--timeout-ms N]
//
// Connects to our Foxglove WebSocket server the way Foxglove Studio does: FoxgloveClient from
// @foxglove/ws-protocol over the `ws` package, offering subprotocol foxglove.websocket.v1. Nothing
// of ours is used. Checks serverInfo, the advertise of /df/test/blob (cdr, omgidl schema
// df::test::Blob, which @foxglove/omgidl-parser must parse), subscribes to it, and checks the 4
// messages that tests/unit/foxglove_ws/ws_js_test_server.cpp publishes: subscription id, log time
// and payload bytes (computed here from the same contract), and the decoded Blob fields. Messages
// of the channel it did not subscribe to must not arrive. Prints a JSON summary, closes, exits 0;
// exits 1 with the reason on stderr otherwise.
import pkg from "@foxglove/ws-protocol";
import { parseIDL } from "@foxglove/omgidl-parser";
import { MessageReader } from "@foxglove/omgidl-serialization";
import WebSocket from "ws";

const { FoxgloveClient } = pkg;

const url = process.argv[2];
const timeoutArg = process.argv.indexOf("--timeout-ms");
const timeoutMs = timeoutArg > 0 ? Number(process.argv[timeoutArg + 1]) : 20000;
if (!url) {
  process.stderr.write("usage: node ws_client_check.mjs ws://HOST:PORT [--timeout-ms N]\n");
  process.exit(2);
}

function fail(message) {
  process.stderr.write(`ws_client_check: ${message}\n`);
  process.exit(1);
}

// The contract with ws_js_test_server.cpp.
const SIZES = [1, 1000, 65539, 1000000];
const FIRST_LOG_TIME_NS = 1700000000000000000n;
const LOG_TIME_STEP_NS = 1000000007n;
function expectedBlob(k) {
  const n = SIZES[k];
  const bytes = new Uint8Array(4 + 4 + 4 + n);
  const view = new DataView(bytes.buffer);
  bytes.set([0x00, 0x01, 0x00, 0x00], 0); // CDR_LE encapsulation
  view.setUint32(4, k, true);
  view.setUint32(8, n, true);
  for (let i = 0; i < n; ++i) bytes[12 + i] = (k * 37 + i * 11) & 0xff;
  return bytes;
}

const ws = new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
const client = new FoxgloveClient({ ws });
const summary = { url, serverInfo: null, channel: null, messages: [] };
let subscriptionId;
let reader;

const timer = setTimeout(
  () => fail(`timed out after ${timeoutMs} ms: ${JSON.stringify(summary)}`),
  timeoutMs,
);

client.on("error", (e) => fail(`client error: ${e?.message ?? e}`));
client.on("close", () => {
  if (summary.messages.length < SIZES.length) fail(`server closed early: ${JSON.stringify(summary)}`);
});
client.on("open", () => {
  if (ws.protocol !== FoxgloveClient.SUPPORTED_SUBPROTOCOL) {
    fail(`server selected subprotocol "${ws.protocol}"`);
  }
});
client.on("status", (s) => fail(`server status (level ${s.level}): ${s.message}`));
client.on("serverInfo", (info) => {
  if (info.name !== "DetectFusion ws test") fail(`serverInfo name "${info.name}"`);
  if (!Array.isArray(info.capabilities)) fail("serverInfo without capabilities");
  summary.serverInfo = { name: info.name, capabilities: info.capabilities, sessionId: info.sessionId };
});
client.on("advertise", (channels) => {
  if (summary.serverInfo === null) fail("advertise before serverInfo");
  const channel = channels.find((c) => c.topic === "/df/test/blob");
  if (!channel || subscriptionId !== undefined) return;
  if (channel.encoding !== "cdr") fail(`encoding "${channel.encoding}", expected "cdr"`);
  if (channel.schemaName !== "df::test::Blob") fail(`schemaName "${channel.schemaName}"`);
  if (channel.schemaEncoding !== "omgidl") fail(`schemaEncoding "${channel.schemaEncoding}"`);
  try {
    reader = new MessageReader(channel.schemaName, parseIDL(channel.schema));
  } catch (e) {
    fail(`Foxglove cannot parse the schema: ${e?.message ?? e}`);
  }
  summary.channel = { id: channel.id, topic: channel.topic, schemaName: channel.schemaName };
  subscriptionId = client.subscribe(channel.id);
});
client.on("message", ({ subscriptionId: id, timestamp, data }) => {
  const k = summary.messages.length;
  if (id !== subscriptionId) fail(`message for subscription ${id}, subscribed ${subscriptionId}`);
  if (k >= SIZES.length) fail(`more than ${SIZES.length} messages`);
  const expectedTime = FIRST_LOG_TIME_NS + BigInt(k) * LOG_TIME_STEP_NS;
  if (timestamp !== expectedTime) fail(`message ${k}: log time ${timestamp}, expected ${expectedTime}`);
  const got = new Uint8Array(data.buffer, data.byteOffset, data.byteLength);
  const want = expectedBlob(k);
  if (got.length !== want.length) fail(`message ${k}: ${got.length} bytes, expected ${want.length}`);
  const diff = got.findIndex((b, i) => b !== want[i]);
  if (diff >= 0) fail(`message ${k}: byte ${diff} is ${got[diff]}, expected ${want[diff]}`);
  const decoded = reader.readMessage(got);
  if (decoded.seq !== k || decoded.data.length !== SIZES[k]) {
    fail(`message ${k}: decoded seq ${decoded.seq}, ${decoded.data.length} data bytes`);
  }
  summary.messages.push({ seq: decoded.seq, bytes: got.length, logTimeNs: timestamp.toString() });
  if (summary.messages.length === SIZES.length) {
    clearTimeout(timer);
    process.stdout.write(`${JSON.stringify(summary)}\n`);
    // A message on the unsubscribed channel would have arrived before these (published first).
    client.close();
  }
});

#!/usr/bin/env node
// Usage: node bridge_watch.mjs ws://HOST:PORT SECONDS [--stall]
//
// A Foxglove WebSocket client (FoxgloveClient of @foxglove/ws-protocol over `ws`, as Studio)
// that subscribes to every channel `df_tap bridge` advertises and, for SECONDS, counts messages
// and bytes per channel; prints JSON {channels: {topic: {messages, bytes}}, seconds} (seconds:
// from the first message to the last). With
// --stall it subscribes and then stops reading its socket (a client that stalls), and prints
// nothing but {stalled: true} at the end. For tests/bench/run_bridge_bench.sh.
import pkg from "@foxglove/ws-protocol";
import WebSocket from "ws";

const { FoxgloveClient } = pkg;
const [url, secondsArg, flag] = process.argv.slice(2);
const seconds = Number(secondsArg);
if (!url || !(seconds > 0)) {
  process.stderr.write("usage: node bridge_watch.mjs ws://HOST:PORT SECONDS [--stall]\n");
  process.exit(2);
}
const stall = flag === "--stall";
const ws = new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]);
const client = new FoxgloveClient({ ws });
const topics = new Map();
const counts = {};
let start;
client.on("error", (e) => {
  process.stderr.write(`bridge_watch: ${e?.message ?? e}\n`);
  process.exit(1);
});
client.on("advertise", (channels) => {
  for (const c of channels) {
    topics.set(client.subscribe(c.id), c.topic);
    counts[c.topic] = { messages: 0, bytes: 0 };
  }
  if (stall) setTimeout(() => ws._socket.pause(), 500);
  start ??= Date.now();
});
let first;
let last;
client.on("message", ({ subscriptionId, data }) => {
  last = Date.now();
  first ??= last;
  const c = counts[topics.get(subscriptionId)];
  c.messages += 1;
  c.bytes += data.byteLength;
});
setTimeout(() => {
  process.stdout.write(`${JSON.stringify(stall ? { stalled: true } : { channels: counts, seconds: first ? (last - first) / 1000 : 0 })}\n`);
  process.exit(0);
}, seconds * 1000);

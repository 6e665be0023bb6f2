// A ROS 2 subscriber that is not ours: Foxglove's pure-JavaScript RTPS participant and ROS 2 node
// (@foxglove/ros2 on @foxglove/rtps), fetched with its dependencies by
// scripts/fetch-ros2-test-peers.sh into data/npm-ros2/node_modules/ (resolved from there, so no
// NODE_PATH is needed). Each message's raw CDR payload is decoded by @foxglove/rosmsg2-serialization
// against the official ROS 2 Humble definitions (@foxglove/rosmsg-msgs-common), as peer_bags.cjs
// does for bags.
//
//   node tests/ros2/ros2_listener.cjs --topic /lrdslam/pose:geometry_msgs/msg/PoseStamped
//       [--topic NAME:TYPE ...] [--domain D] [--seconds S] [--until-count TOPIC=N ...]
//       [--discovery] [--out FILE] [--interface 127.0.0.1] [--verbose]
//
//   --domain D            DDS domain (default $ROS_DOMAIN_ID, else 0)
//   --seconds S           listen this long, then exit 0 (default 10)
//   --until-count T=N     exit as soon as every such topic has N messages (repeatable; T as in --topic,
//                         or ros_discovery_info)
//   --topic NAME:TYPE     subscribe (reliable, transient local, keep last 1: the publisher must be
//                         reliable and transient local to match)
//   --discovery           also subscribe to the DDS topic ros_discovery_info
//                         (rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_, Humble layout)
//   --out FILE            JSON lines go to FILE (written as they come) instead of stdout
//   --interface ADDR      the IPv4 address to discover and talk on (default 127.0.0.1)
//   --verbose             RTPS discovery log on stderr
//
// Output, JSON lines:
//   {"topic", "type", "t" (receive time, s), "seq" (writer sequence number), "source_t" (the writer's
//    INFO_TS time, s, where the library has one; else, as for fragmented samples, the receive time),
//    "publisher" (writer GUID, hex), "msg"}                                  one per message
//   {"published_topics": [[topic, type], ...]}      at the end: every rt/ writer seen (RosNode's
//                                                   getPublishedTopics; writers that left stay listed)
//   {"done": true, "counts": {topic: n}, "until_met": bool, "first_t": {topic: s}, "start_t": s}
// Lines come in arrival order, not per writer in sequence order: a reader that matches while the
// writer is publishing gets the live samples first and the writer's transient-local history (its
// earlier samples) after them, so sort by "seq" (or a stamp) where order matters.
// In "msg", 64-bit integers are strings; uint8/int8 arrays (image, point cloud, grid data) are
// {"length", "sha256"} of their bytes; other numeric arrays are lists up to 64 elements, else
// {"length", "sha256"} of their little-endian bytes; a Gid's data (ros_discovery_info) is hex.
// A message that fails to decode gives {"topic", ..., "error", "length"} instead of "msg".
// A message repeated by a writer (same writer GUID and sequence number) is written once.
// Stderr gets one line "ros2_listener: listening ..." once the participant is up.
//
// Discovery is RTPS multicast SPDP (239.255.0.1, port 7400 + 250 * domain); the sockets are pinned
// to --interface (multicast egress and group membership), so loopback works without a multicast
// route, as long as the publisher also sends SPDP multicast on that interface (Cyclone DDS:
// NetworkInterface address="127.0.0.1" multicast="true", AllowMulticast spdp).
"use strict";
const crypto = require("crypto");
const fs = require("fs");
const path = require("path");
const { createRequire } = require("module");

// Modules from data/npm-ros2/node_modules (the repository's), else the normal lookup (NODE_PATH).
const localRequire = createRequire(path.join(__dirname, "..", "..", "data", "npm-ros2", "package.json"));
function resolvePeer(name) {
  try {
    return localRequire.resolve(name);
  } catch (e) {
    if (e.code !== "MODULE_NOT_FOUND") throw e;
    return require.resolve(name);
  }
}
const peersRequire = (name) => require(resolvePeer(name));
const { RosNode, rosTopicToDds } = peersRequire("@foxglove/ros2");
const { UdpSocketNode } = peersRequire("@foxglove/ros2/nodejs");
// The @foxglove/rtps that @foxglove/ros2 itself uses (nested under it), for its enums and GUIDs.
const rtps = createRequire(resolvePeer("@foxglove/ros2"))("@foxglove/rtps");
const { MessageReader } = peersRequire("@foxglove/rosmsg2-serialization");
const { parse } = peersRequire("@foxglove/rosmsg");
const { ros2humble } = peersRequire("@foxglove/rosmsg-msgs-common");

const DISCOVERY_TOPIC = "ros_discovery_info";
const DISCOVERY_TYPE = "rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_";
// rmw_dds_common (ROS 2 Humble): msg/ParticipantEntitiesInfo.msg, msg/NodeEntitiesInfo.msg, msg/Gid.msg.
const DISCOVERY_MSG = `Gid gid
NodeEntitiesInfo[] node_entities_info_seq
================================================================================
MSG: rmw_dds_common/NodeEntitiesInfo
string<=256 node_namespace
string<=256 node_name
Gid[] reader_gid_seq
Gid[] writer_gid_seq
================================================================================
MSG: rmw_dds_common/Gid
char[24] data
`;

function usage(message) {
  process.stderr.write(`ros2_listener: ${message}\nusage: node ros2_listener.cjs --topic NAME:pkg/msg/Type [--topic ...] [--domain D] [--seconds S] [--until-count TOPIC=N] [--discovery] [--out FILE] [--interface ADDR] [--verbose]\n`);
  process.exit(2);
}

function parseArgs(argv) {
  const opts = { domain: Number(process.env.ROS_DOMAIN_ID || 0), seconds: 10, until: new Map(), topics: [], discovery: false, out: undefined, iface: "127.0.0.1", verbose: false };
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i];
    const value = () => (i + 1 < argv.length ? argv[++i] : usage(`${a} needs a value`));
    if (a === "--domain") opts.domain = Number(value());
    else if (a === "--seconds") opts.seconds = Number(value());
    else if (a === "--until-count") {
      const v = value(), eq = v.lastIndexOf("=");
      if (eq <= 0 || !(Number(v.slice(eq + 1)) >= 0)) usage(`bad --until-count ${v}`);
      opts.until.set(v.slice(0, eq), Number(v.slice(eq + 1)));
    } else if (a === "--topic") {
      const v = value(), colon = v.lastIndexOf(":");
      if (colon <= 0 || v.slice(colon + 1).split("/").length !== 3) usage(`bad --topic ${v} (want /name:pkg/msg/Type)`);
      opts.topics.push({ topic: v.slice(0, colon), type: v.slice(colon + 1) });
    } else if (a === "--discovery") opts.discovery = true;
    else if (a === "--out") opts.out = value();
    else if (a === "--interface") opts.iface = value();
    else if (a === "--verbose") opts.verbose = true;
    else usage(`unknown argument ${a}`);
  }
  if (!Number.isInteger(opts.domain) || opts.domain < 0 || opts.domain > 232) usage(`bad domain ${opts.domain}`);
  if (!(opts.seconds > 0)) usage(`bad --seconds ${opts.seconds}`);
  if (opts.topics.length === 0 && !opts.discovery) usage("nothing to listen to (--topic or --discovery)");
  return opts;
}

const definitionsIn = require("./definitions.cjs");
const officialDefinitions = (rosType) => definitionsIn(ros2humble, rosType);

const sha256 = (bytes) => crypto.createHash("sha256").update(bytes).digest("hex");
const digest = (a) => ({ length: a.length, sha256: sha256(new Uint8Array(a.buffer, a.byteOffset, a.byteLength)) });

// A decoded message as JSON-friendly values (see the header).
function plain(value) {
  if (typeof value === "bigint") return value.toString();
  if (ArrayBuffer.isView(value)) {
    if (value instanceof Uint8Array || value instanceof Int8Array || value instanceof Uint8ClampedArray) return digest(value);
    if (value.length > 64) return digest(value);
    return Array.from(value, plain);
  }
  if (Array.isArray(value)) return value.map(plain);
  if (value !== null && typeof value === "object") {
    const out = {};
    for (const [k, v] of Object.entries(value)) out[k] = plain(v);
    return out;
  }
  if (typeof value === "number" && !Number.isFinite(value)) return String(value);
  return value;
}

// ros_discovery_info with each Gid's bytes as hex.
function plainDiscovery(msg) {
  const gid = (g) => ({ data: Buffer.from(g.data).toString("hex") });
  return {
    gid: gid(msg.gid),
    node_entities_info_seq: msg.node_entities_info_seq.map((n) => ({
      node_namespace: n.node_namespace,
      node_name: n.node_name,
      reader_gid_seq: n.reader_gid_seq.map(gid),
      writer_gid_seq: n.writer_gid_seq.map(gid),
    })),
  };
}

// Node's UDP sockets with multicast egress and group membership on one interface (the library
// joins the SPDP group on the default one and sends with the route's interface).
function pinnedSocketCreate(iface) {
  return async (options) => {
    const socket = await UdpSocketNode.Create(options);
    const bind = socket.bind.bind(socket);
    const addMembership = socket.addMembership.bind(socket);
    socket.bind = async (bindOptions) => {
      await bind(bindOptions);
      await socket.setMulticastInterface(iface);
      await socket.setMulticastLoopback(true);
    };
    socket.addMembership = async (group) => addMembership(group, iface);
    return socket;
  };
}

async function main() {
  const opts = parseArgs(process.argv.slice(2));
  const startT = Date.now() / 1000;
  const log = (level) => (msg) => process.stderr.write(`ros2_listener [${level}] ${msg}\n`);
  const rtpsLog = opts.verbose ? { debug: () => {}, info: log("info"), warn: log("warn"), error: log("error") } : { error: log("error") };

  const node = new RosNode({
    name: "ros2_listener",
    domainId: opts.domain,
    addresses: [opts.iface],
    udpSocketCreate: pinnedSocketCreate(opts.iface),
    log: rtpsLog,
  });
  const participant = node._participant; // the RTPS participant (for ros_discovery_info, no rt/ name)

  // DDS topic name -> what we print and how we decode.
  const byDdsTopic = new Map();
  const counts = {};
  const firstT = {};
  for (const { topic, type } of opts.topics) {
    const ddsTopic = rosTopicToDds(topic);
    let definitions;
    try {
      definitions = officialDefinitions(type);
    } catch (e) {
      usage(`--topic ${topic}:${type}: ${e.message} (in @foxglove/rosmsg-msgs-common ros2humble)`);
    }
    byDdsTopic.set(ddsTopic, { topic, type, reader: new MessageReader(definitions), toPlain: plain });
    counts[topic] = 0;
  }
  if (opts.discovery) {
    byDdsTopic.set(DISCOVERY_TOPIC, { topic: DISCOVERY_TOPIC, type: DISCOVERY_TYPE, reader: new MessageReader(parse(DISCOVERY_MSG, { ros2: true })), toPlain: plainDiscovery });
    counts[DISCOVERY_TOPIC] = 0;
  }
  for (const t of opts.until.keys()) if (!(t in counts)) usage(`--until-count ${t}: not a --topic${opts.discovery ? " or ros_discovery_info" : ""}`);

  const outFd = opts.out !== undefined ? fs.openSync(opts.out, "w") : undefined;
  const emit = (obj) => {
    const line = JSON.stringify(obj) + "\n";
    if (outFd !== undefined) fs.writeSync(outFd, line);
    else process.stdout.write(line);
  };

  let finished = false;
  const untilMet = () => opts.until.size > 0 && [...opts.until].every(([t, n]) => counts[t] >= n);
  const finish = async () => {
    if (finished) return;
    finished = true;
    clearTimeout(timer);
    emit({ published_topics: node.getPublishedTopics() });
    emit({ done: true, counts, until_met: untilMet(), first_t: firstT, start_t: startT });
    try {
      await Promise.race([node.shutdown(), new Promise((r) => setTimeout(r, 500))]);
    } catch (e) {
      log("warn")(`shutdown: ${e}`);
    }
    if (outFd !== undefined) {
      fs.closeSync(outFd);
      process.exit(0);
    }
    process.stdout.write("", () => process.exit(0));
  };

  // Every sample of our subscriptions, once per writer and sequence number.
  const seen = new Set();
  participant.on("userData", (userData) => {
    const entry = byDdsTopic.get(userData.subscription.topicName);
    if (entry === undefined || finished) return;
    const publisher = rtps.makeGuid(userData.publication.guidPrefix, userData.publication.entityId);
    const key = `${publisher}/${userData.writerSeqNumber}`;
    if (seen.has(key)) return;
    seen.add(key);
    const data = userData.serializedData;
    const line = { topic: entry.topic, type: entry.type, t: Date.now() / 1000, seq: Number(userData.writerSeqNumber) };
    if (userData.timestamp !== undefined) line.source_t = userData.timestamp.sec + userData.timestamp.nsec / 1e9;
    line.publisher = publisher;
    try {
      line.msg = entry.toPlain(entry.reader.readMessage(data));
    } catch (e) {
      line.error = String(e && e.message ? e.message : e);
      line.length = data.length;
    }
    emit(line);
    counts[entry.topic] += 1;
    if (firstT[entry.topic] === undefined) firstT[entry.topic] = line.t;
    if (untilMet()) void finish();
  });
  participant.on("error", (e) => log("error")(String(e)));
  if (opts.verbose) {
    node.on("discoveredParticipant", (p) => log("info")(`participant ${p.guidPrefix} at +${(Date.now() / 1000 - startT).toFixed(3)} s`));
    node.on("discoveredPublication", (p) => log("info")(`publication ${p.topicName} (${p.typeName}) at +${(Date.now() / 1000 - startT).toFixed(3)} s`));
  }

  const timer = setTimeout(() => void finish(), opts.seconds * 1000);
  process.on("SIGTERM", () => void finish());
  process.on("SIGINT", () => void finish());

  await node.start();
  const DURATION_INFINITE = { sec: 0x7fffffff, nsec: 0xffffffff };
  for (const { topic, type } of opts.topics) node.subscribe({ topic, dataType: type, skipParsing: true });
  if (opts.discovery) {
    // rmw subscribes to it reliable, transient local, keep last (depth 1 here, as RosNode's readers).
    participant.subscribe({
      topicName: DISCOVERY_TOPIC,
      typeName: DISCOVERY_TYPE,
      durability: rtps.Durability.TransientLocal,
      reliability: { kind: rtps.Reliability.Reliable, maxBlockingTime: DURATION_INFINITE },
      history: { kind: rtps.HistoryKind.KeepLast, depth: 1 },
    });
  }
  process.stderr.write(`ros2_listener: listening on domain ${opts.domain} (${opts.iface}) as ${participant.attributes.guidPrefix}\n`);
}

main().catch((e) => {
  process.stderr.write(`ros2_listener: ${e && e.stack ? e.stack : e}\n`);
  process.exit(1);
});

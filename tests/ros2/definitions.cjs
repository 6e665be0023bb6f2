// The official definition of a ROS 2 type and of every type its fields use, root first, as
// @foxglove/rosmsg2-serialization's MessageReader and MessageWriter take them, from a table of
// definitions (@foxglove/rosmsg-msgs-common's ros2humble). Shared by the bag and DDS peers.
"use strict";

module.exports = function officialDefinitions(table, rosType) {
  const out = [];
  const seen = new Set();
  const visit = (name) => {
    if (seen.has(name)) return;
    seen.add(name);
    const def = table[name];
    if (!def) throw new Error(`no official definition of ${name}`);
    out.push(def);
    for (const field of def.definitions) if (field.isComplex) visit(field.type);
  };
  visit(rosType.replace("/msg/", "/"));
  return out;
};

#version 460
#extension GL_GOOGLE_include_directive : require
// Pass set_dispatch_args: turns a queue counter into indirect dispatch arguments, so the next
// pass runs exactly as many workgroups as there are queued items (no host round-trip), and adds
// the queue's size to the ray statistics counter push.args.z (none if it is kCounterCount).
// Reads: counters[push.args.x]. Writes: dispatchArgs[3 * push.args.y ...], counters[push.args.z].
// Dispatch: 1 group.
#include "lib/common.glsl"
#include "lib/bindings.glsl"

layout(local_size_x = 1) in;
layout(push_constant) uniform Push { PassPush push; };

void main() {
  uint count = counters[push.args.x];
  uint record = 3u * push.args.y;
  dispatchArgs[record + 0u] = (count + kWorkgroupSize - 1u) / kWorkgroupSize;
  dispatchArgs[record + 1u] = 1u;
  dispatchArgs[record + 2u] = 1u;
  if (push.args.z < kCounterCount) counters[push.args.z] += count;
}

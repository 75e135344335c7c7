// troupe-node's exit statuses. Its systemd unit restarts the node after a
// failure a retry may mend (hardware that appears late) and not after one
// only a person can mend, so the two must differ.
#pragma once

namespace troupe {

/// Could not start now: a device it drives is not there, its port is
/// taken. The unit retries.
inline constexpr int kExitNotYet = 1;
/// A bad command line, or plain TCP beyond loopback not asked for
/// (--insecure). Not retried.
inline constexpr int kExitUsage = 2;
/// The config, or a file it names (a key), must be fixed first:
/// sysexits.h's EX_CONFIG, which service managers and scripts know. Not
/// retried: the same file would fail the same way every 2 s.
inline constexpr int kExitConfig = 78;

}  // namespace troupe

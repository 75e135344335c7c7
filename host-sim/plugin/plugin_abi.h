// The one ABI of everything troupe-sim loads at run time: controllers
// (Stage's `ctrl`), RoboCup sensor, motion and player plugins. A plugin is
// a shared library `<name>.so` exporting one C function,
//
//   extern "C" const TroupePluginInfo* troupe_plugin_v1(void);
//
// that says which ABI it was built for, what kind of plugin it is, the
// version of that kind's C++ interface, its name, and how to make and
// destroy instances (inside the library, so no allocator crosses the
// boundary). Header-only and C-compatible: a plugin includes this and its
// kind's interface header, and links nothing of the simulator.
#pragma once

#include <stdint.h>

/// Bumped when TroupePluginInfo changes; the entry's name carries it too.
#define TROUPE_PLUGIN_ABI_VERSION 1
#define TROUPE_PLUGIN_ENTRY "troupe_plugin_v1"

/// What `create` returns: the interface pointer of the kind.
enum TroupePluginKind {
  TROUPE_PLUGIN_CONTROLLER = 1, /* troupe::sim::Controller* (host-sim/sim/controller.h) */
  TROUPE_PLUGIN_SENSOR = 2,     /* troupe::robocup::SensorPlugin* (host-sim/robocup/api/plugin.h) */
  TROUPE_PLUGIN_MOTION = 3,     /* troupe::robocup::MotionPlugin* */
  TROUPE_PLUGIN_PLAYER = 4,     /* troupe::robocup::PlayerPlugin* */
};

struct TroupePluginInfo {
  uint32_t abi_version;       /* TROUPE_PLUGIN_ABI_VERSION */
  uint32_t kind;              /* a TroupePluginKind */
  uint32_t interface_version; /* the kind's interface version the plugin was built against */
  const char* name;           /* equal to the library's file name without ".so" */
  /* A new instance, configured from `args` (a controller's "speed=0.3";
     null for kinds configured afterwards), or null when they are bad. */
  void* (*create)(const char* args);
  void (*destroy)(void* instance);
};

/// Marks a plugin's entry function: C linkage, visible from the library
/// (plugins are built with hidden visibility).
#define TROUPE_PLUGIN_EXPORT extern "C" __attribute__((visibility("default")))

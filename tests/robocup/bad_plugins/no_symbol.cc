// A shared library on the plugin path that is not a plugin: it exports no
// entry function. Loading it must fail with an error naming it.
extern "C" __attribute__((visibility("default"))) int troupe_not_the_entry() {
  return 42;
}

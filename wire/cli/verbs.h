#pragma once

#include <span>
#include <string>

#include "wire/cli/cli.h"

namespace troupe::cli {

/// A body built from command-line words.
struct Built {
  wire::Body type = wire::Body::NONE;
  flatbuffers::Offset<void> body = 0;
};

struct Verb {
  wire::Interface iface;
  wire::Kind kind;  // Command or Request
  const char* name;
  const char* args;  // for help: "VX VY VA"
  const char* help;  // what it does, with units
  uint8_t subtype;
  size_t min_args, max_args;
  bool (*build)(flatbuffers::FlatBufferBuilder& b, std::span<const std::string> args, Built& out,
                std::string& error);
};

const Verb* find_verb(wire::Interface iface, wire::Kind kind, const std::string& name);

}  // namespace troupe::cli

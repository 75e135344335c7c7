// troupe config: node configs on the host. `compile` turns a JSON config
// into the binary a board's node reads (what the board build does with
// flatc, for any config and any board), `print` shows a config as a
// board's node would run it.
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string_view>
#include <iterator>
#include <string>
#include <vector>

#include "flatbuffers/reflection.h"
#include "runtime/board_schemas.h"
#include "runtime/config_edit.h"
#include "runtime/config_json.h"
#include "wire/cli/args.h"

namespace {

using troupe::cli::kExitFailure;

const troupe::BoardSchema* find_board(const std::string& name, std::string& names) {
  for (const troupe::BoardSchema* b = troupe::kBoardSchemas; b->board != nullptr; ++b) {
    if (name == b->board) return b;
    names += (names.empty() ? "" : ", ") + std::string(b->board);
  }
  return nullptr;
}

// The config at `path` as the board's binary: JSON parsed against the
// board's schema, a binary one verified against it.
bool load(const troupe::BoardSchema& board, const std::string& path, std::vector<uint8_t>& config,
          std::string& error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    error = path + ": cannot open: " + strerror(errno);
    return false;
  }
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const reflection::Schema& schema = *reflection::GetSchema(board.schema);
  // A binary config carries the schema's identifier after its root offset.
  // (Compared by hand: GCC 12 takes flatbuffers::BufferHasIdentifier on a
  // string's bytes for an overread.)
  const std::string_view ident = schema.file_ident() ? schema.file_ident()->string_view() : std::string_view();
  if (text.size() >= 8 && ident.size() == flatbuffers::kFileIdentifierLength &&
      std::string_view(text).substr(4, ident.size()) == ident) {
    config.assign(text.begin(), text.end());
    if (!flatbuffers::Verify(schema, *schema.root_table(), config.data(), config.size())) {
      error = path + ": not a valid node config for board " + board.board;
      return false;
    }
    return true;
  }
  return troupe::parse_node_config_json(board.schema, *board.size, board.board,
                                        *board.drivers ? board.drivers : "none", text, path, config, error);
}

}  // namespace

int main(int argc, char** argv) {
  std::string command, path, board_name, out_path;
  std::vector<std::string> sets;
  auto app = troupe::cli::make_app(
      "troupe config",
      {"troupe config compile CONFIG.json --board BOARD -o CONFIG.bin [--set INSTANCE.KEY=VALUE]...\n"
       "       troupe config print CONFIG --board BOARD [--set INSTANCE.KEY=VALUE]...",
       "Node configs for a board. `compile` checks a JSON config against the schema of\n"
       "BOARD (the drivers boards/BOARD compiles in: a driver it lacks is refused) and\n"
       "writes the binary its troupe-node reads, as the board build does; `print` shows\n"
       "a JSON or compiled config as that node would run it (troupe-node --print-config).\n"
       "--set changes an option first, as troupe-node --set does.\n",
       {"troupe config compile examples/nodes/pioneer-p3dx.json --board pioneer-p3dx -o pioneer-p3dx.bin",
        "troupe config compile examples/nodes/pioneer-p3dx.json --board pioneer-p3dx -o usb.bin --set "
        "p2os.port=/dev/ttyUSB1",
        "troupe config print pioneer-p3dx.bin --board pioneer-p3dx"}});
  app->add_option("COMMAND", command, "compile or print")
      ->required()
      ->check(CLI::IsMember({"compile", "print"}));
  app->add_option("CONFIG", path, "the node config, JSON (or compiled, for print)")->required();
  app->add_option("--board", board_name, "the board whose node reads it (a folder under boards/)")
      ->type_name("BOARD")
      ->required();
  auto* out =
      app->add_option("-o,--out", out_path, "where the compiled config goes (compile)")->type_name("FILE");
  app->add_option("--set", sets, "set an option (INSTANCE.KEY=VALUE) or node setting (KEY=VALUE); repeatable")
      ->type_name("ASSIGNMENT")
      ->expected(1)
      ->take_all();
  if (int rc = troupe::cli::parse(*app, argc, argv); rc >= 0) return rc;
  if (command == "compile" && out->count() == 0)
    return troupe::cli::usage_error(*app, "compile needs -o FILE");
  if (command == "print" && out->count() > 0) return troupe::cli::usage_error(*app, "-o is compile's");

  std::string boards;
  const troupe::BoardSchema* board = find_board(board_name, boards);
  if (board == nullptr) {
    return troupe::cli::usage_error(*app, "no board '" + board_name + "' (boards: " + boards + ")");
  }
  const reflection::Schema& schema = *reflection::GetSchema(board->schema);
  std::vector<uint8_t> config;
  std::string error;
  if (!load(*board, path, config, error)) {
    fprintf(stderr, "troupe config: %s\n", error.c_str());
    return kExitFailure;
  }
  for (const std::string& s : sets) {
    if (!troupe::set_config_value(schema, config, s, error)) {
      return troupe::cli::usage_error(*app, "--set " + s + ": " + error);
    }
  }
  if (command == "print") {
    fputs(troupe::config_to_json(schema, config.data()).c_str(), stdout);
    return 0;
  }
  std::ofstream file(out_path, std::ios::binary | std::ios::trunc);
  file.write(reinterpret_cast<const char*>(config.data()), std::streamsize(config.size()));
  file.close();
  if (!file) {
    fprintf(stderr, "troupe config: %s: cannot write: %s\n", out_path.c_str(), strerror(errno));
    return kExitFailure;
  }
  return 0;
}

#include "host-sim/world/worldfile.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "host-sim/world/tokenizer.h"

namespace troupe::world {
namespace fs = std::filesystem;
namespace {

struct Item;
using Body = std::vector<Item>;

// A statement inside a model's parentheses, before defines are expanded.
struct Item {
  bool is_property = false;
  Property prop;
  std::string word;  // child model type as written
  SourceLoc loc;
  std::shared_ptr<const Body> body;
};

struct Macro {
  std::string parent;
  SourceLoc loc;
  std::shared_ptr<const Body> body;
};

// A child model a define's body brings, expanded once: every later
// instance shares it. Valid while the defines are those it was expanded
// with (a define clears them all), at the same depth and with the same
// defines being expanded around it, so sharing never changes a result.
struct Expanded {
  std::shared_ptr<const Entity> entity;
  size_t models = 0;  // models in it, counted against the limit again
  std::vector<std::string> expanding;
};

void set_property(Entity& e, const Property& p) {
  for (Property& q : e.properties) {
    if (q.name == p.name) {
      q = p;
      return;
    }
  }
  e.properties.push_back(p);
}

class Parser {
 public:
  Parser(Diagnostics& diags, const ParseLimits& limits, Entity& root)
      : diags_(diags), limits_(limits), root_(root) {}

  bool parse_file(const std::string& path, const SourceLoc& from, int depth) {
    std::error_code ec;
    auto size = fs::file_size(path, ec);
    if (ec) {
      diags_.error(from, (depth == 0 ? "cannot open world file '" : "cannot open include file '") + path +
                             "': " + ec.message());
      return false;
    }
    if (size > limits_.max_file_bytes) {
      diags_.error(from,
                   "'" + path + "' is larger than " + std::to_string(limits_.max_file_bytes) + " bytes");
      return false;
    }
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    if (!in && !in.eof()) {
      diags_.error(from, "cannot read '" + path + "': " + std::strerror(errno));
      return false;
    }
    return parse_text(text.str(), path, depth);
  }

  bool parse_text(std::string_view text, const std::string& path, int depth) {
    // Tokens view `text` and carry bare lines; their file is this one.
    struct CurrentFile {
      Parser& p;
      std::shared_ptr<const std::string> saved;
      ~CurrentFile() { p.file_ = saved; }
    } restore{*this, file_};
    std::error_code ec;
    std::string key = fs::weakly_canonical(fs::path(path), ec).string();
    if (ec) key = path;
    for (const std::string& open : include_stack_) {
      if (open == key) {
        diags_.error({std::make_shared<const std::string>(path), 0},
                     "include cycle: '" + path + "' includes itself");
        return false;
      }
    }
    auto file = std::make_shared<const std::string>(path);
    file_ = file;
    std::vector<Token> tokens;
    if (!tokenize(text, file, tokens, diags_)) return false;
    include_stack_.push_back(key);
    size_t i = 0;
    bool ok = statements(tokens, i, file, depth);
    include_stack_.pop_back();
    return ok;
  }

 private:
  SourceLoc at(const Token& t) const { return {file_, t.line}; }

  bool statements(const std::vector<Token>& t, size_t& i, const std::shared_ptr<const std::string>& file,
                  int depth) {
    while (i < t.size()) {
      const Token& tok = t[i];
      if (tok.kind != TokenKind::Word) {
        diags_.error(at(tok), "expected a property or a model, found " + describe(tok));
        return false;
      }
      if (tok.text == "include") {
        if (i + 1 >= t.size() || t[i + 1].kind != TokenKind::String) {
          diags_.error(at(tok), "include needs a quoted file name");
          return false;
        }
        if (depth + 1 > limits_.max_include_depth) {
          diags_.error(at(tok), "includes nested deeper than " + std::to_string(limits_.max_include_depth));
          return false;
        }
        fs::path inc(t[i + 1].text);
        if (inc.is_relative()) inc = fs::path(*file).parent_path() / inc;
        if (!parse_file(inc.string(), at(tok), depth + 1)) return false;
        i += 2;
      } else if (tok.text == "define") {
        if (!define(t, i)) return false;
      } else if (i + 1 < t.size() && t[i + 1].kind == TokenKind::OpenEntity) {
        Item item;
        if (!entity_item(t, i, 1, item)) return false;
        auto e = std::make_shared<Entity>();
        if (!expand(item.word, item.loc, *item.body, false, 1, *e)) return false;
        root_.children.push_back(std::move(e));
      } else {
        Property p;
        if (!property(t, i, p)) return false;
        set_property(root_, p);
      }
    }
    return true;
  }

  bool define(const std::vector<Token>& t, size_t& i) {
    const Token& def = t[i];
    if (i + 3 >= t.size() || t[i + 1].kind != TokenKind::Word || t[i + 2].kind != TokenKind::Word ||
        t[i + 3].kind != TokenKind::OpenEntity) {
      diags_.error(at(def), "define needs a name, a parent type and a body: define NAME PARENT ( ... )");
      return false;
    }
    const std::string name(t[i + 1].text);
    Macro m{std::string(t[i + 2].text), at(def), nullptr};
    i += 3;
    auto body = std::make_shared<Body>();
    if (!body_items(t, i, 1, *body, m.loc, name)) return false;
    m.body = std::move(body);
    auto [it, inserted] = macros_.emplace(name, m);
    if (!inserted) {
      // Stage looks macros up in definition order, so the first one wins.
      diags_.warn(m.loc, "'" + name + "' is already defined at " + it->second.loc.str() +
                             "; this definition is ignored");
    } else {
      // A new name may change what a define's body expands to.
      expanded_.clear();
    }
    return true;
  }

  // t[i] is the type word, t[i+1] is '('.
  bool entity_item(const std::vector<Token>& t, size_t& i, int depth, Item& item) {
    item.word = t[i].text;
    item.loc = at(t[i]);
    if (depth > limits_.max_depth) {
      diags_.error(item.loc, "models nested deeper than " + std::to_string(limits_.max_depth));
      return false;
    }
    i += 1;
    auto body = std::make_shared<Body>();
    if (!body_items(t, i, depth, *body, item.loc, item.word)) return false;
    item.body = std::move(body);
    return true;
  }

  // t[i] is '('; consumes through the matching ')'.
  bool body_items(const std::vector<Token>& t, size_t& i, int depth, Body& out, const SourceLoc& open,
                  const std::string& what) {
    ++i;
    while (true) {
      if (i >= t.size()) {
        diags_.error(open, "missing ')' for '" + what + "' opened here");
        return false;
      }
      const Token& tok = t[i];
      if (tok.kind == TokenKind::CloseEntity) {
        ++i;
        return true;
      }
      if (tok.kind != TokenKind::Word) {
        diags_.error(at(tok), "expected a property or a model inside '" + what + "', found " + describe(tok));
        return false;
      }
      if (tok.text == "include" || tok.text == "define") {
        diags_.error(at(tok), "'" + std::string(tok.text) + "' is only allowed outside models");
        return false;
      }
      Item item;
      if (i + 1 < t.size() && t[i + 1].kind == TokenKind::OpenEntity) {
        if (!entity_item(t, i, depth + 1, item)) return false;
      } else {
        item.is_property = true;
        item.loc = at(tok);
        if (!property(t, i, item.prop)) return false;
      }
      out.push_back(std::move(item));
    }
  }

  // t[i] is the property name.
  bool property(const std::vector<Token>& t, size_t& i, Property& p) {
    p.name = t[i].text;
    p.loc = at(t[i]);
    ++i;
    if (i >= t.size()) {
      diags_.error(p.loc, "'" + p.name + "' has no value");
      return false;
    }
    auto value_of = [this](const Token& v) {
      return Value{v.kind == TokenKind::String, v.number, std::string(v.text), at(v)};
    };
    const Token& v = t[i];
    if (v.kind == TokenKind::Number || v.kind == TokenKind::String) {
      p.values = ValueList({value_of(v)});
      ++i;
      return true;
    }
    if (v.kind != TokenKind::OpenTuple) {
      diags_.error(at(v),
                   "'" + p.name + "' needs a number, a quoted string or a [tuple], found " + describe(v));
      return false;
    }
    p.tuple = true;
    std::vector<Value> values;
    for (++i; i < t.size(); ++i) {
      if (t[i].kind == TokenKind::CloseTuple) {
        ++i;
        p.values = ValueList(std::move(values));
        return true;
      }
      if (t[i].kind != TokenKind::Number && t[i].kind != TokenKind::String) {
        diags_.error(at(t[i]), "a tuple holds numbers and quoted strings, found " + describe(t[i]));
        return false;
      }
      values.push_back(value_of(t[i]));
    }
    diags_.error(at(v), "missing ']' for '" + p.name + "'");
    return false;
  }

  // `shared_body`: `body` is a define's (it lives as long as the parser),
  // so its child models may be expanded once and shared.
  bool expand(const std::string& word, const SourceLoc& loc, const Body& body, bool shared_body, int depth,
              Entity& out) {
    if (depth > limits_.max_depth) {
      diags_.error(loc,
                   "models nested (or defines chained) deeper than " + std::to_string(limits_.max_depth));
      return false;
    }
    if (auto it = macros_.find(word); it != macros_.end()) {
      for (const std::string& active : expanding_) {
        if (active == word) {
          diags_.error(it->second.loc, "'" + word + "' is defined in terms of itself");
          return false;
        }
      }
      expanding_.push_back(word);
      bool ok = expand(it->second.parent, it->second.loc, *it->second.body, true, depth + 1, out);
      expanding_.pop_back();
      if (!ok) return false;
    } else {
      out.type = word;
      if (++models_ > limits_.max_models) {
        diags_.error(loc, "more than " + std::to_string(limits_.max_models) + " models");
        return false;
      }
    }
    out.written_type = word;
    out.loc = loc;
    for (const Item& item : body) {
      if (item.is_property) {
        set_property(out, item.prop);
        continue;
      }
      std::shared_ptr<const Entity> child;
      if (shared_body && !shared_child(item, depth + 1, child)) return false;
      if (!child) {
        auto fresh = std::make_shared<Entity>();
        if (!expand(item.word, item.loc, *item.body, shared_body, depth + 1, *fresh)) return false;
        child = std::move(fresh);
      }
      out.children.push_back(std::move(child));
    }
    return true;
  }

  // `item` (a child model in a define's body) expanded at `depth` into
  // `out`: the one expanded before when it still holds (see Expanded), else
  // expanded now and kept. False after an error (reported). `out` stays
  // null when the shared one would cross the model limit: expanding it
  // afresh then reports the model where it does.
  bool shared_child(const Item& item, int depth, std::shared_ptr<const Entity>& out) {
    const auto key = std::make_pair(&item, depth);
    if (auto it = expanded_.find(key); it != expanded_.end() && it->second.expanding == expanding_) {
      if (models_ + it->second.models > limits_.max_models) return true;
      models_ += it->second.models;
      out = it->second.entity;
      return true;
    }
    const size_t models_before = models_;
    auto fresh = std::make_shared<Entity>();
    if (!expand(item.word, item.loc, *item.body, true, depth, *fresh)) return false;
    expanded_[key] = {fresh, models_ - models_before, expanding_};
    out = std::move(fresh);
    return true;
  }

  Diagnostics& diags_;
  const ParseLimits& limits_;
  Entity& root_;
  // The file being tokenized and parsed (includes nest).
  std::shared_ptr<const std::string> file_;
  std::map<std::pair<const Item*, int>, Expanded> expanded_;
  std::map<std::string, Macro, std::less<>> macros_;
  std::vector<std::string> include_stack_;
  std::vector<std::string> expanding_;
  size_t models_ = 0;
};

void warn_unused_in(const Entity& e, Diagnostics& diags) {
  for (const Property& p : e.properties) {
    if (!p.used) {
      std::string where = e.type == "world" ? "the world" : "model type '" + e.type + "'";
      if (e.written_type != e.type && e.type != "world") where += " (written '" + e.written_type + "')";
      diags.warn(p.loc, "unknown key '" + p.name + "' for " + where + "; ignored");
    }
  }
  for (const Entity& c : e.children) warn_unused_in(c, diags);
}

}  // namespace

const Property* Entity::find(std::string_view name) const {
  for (const Property& p : properties) {
    if (p.name == name) {
      p.used = true;
      return &p;
    }
  }
  return nullptr;
}

bool WorldFile::load(const std::string& path, Diagnostics& diags, const ParseLimits& limits) {
  root_ = Entity{"world", "world", {std::make_shared<const std::string>(path), 0}, {}, {}};
  path_ = path;
  Parser parser(diags, limits, root_);
  return parser.parse_file(path, {std::make_shared<const std::string>(path), 0}, 0);
}

bool WorldFile::parse(std::string_view text, const std::string& path, Diagnostics& diags,
                      const ParseLimits& limits) {
  root_ = Entity{"world", "world", {std::make_shared<const std::string>(path), 0}, {}, {}};
  path_ = path;
  Parser parser(diags, limits, root_);
  return parser.parse_text(text, path, 0);
}

void WorldFile::warn_unused(Diagnostics& diags) const {
  warn_unused_in(root_, diags);
}

std::string WorldFile::resolve_path(const Value& value) const {
  fs::path p(value.text);
  if (p.is_absolute()) return p.string();
  if (value.loc.file) {
    fs::path near = fs::path(*value.loc.file).parent_path() / p;
    std::error_code ec;
    if (fs::exists(near, ec)) return near.string();
  }
  return (fs::path(path_).parent_path() / p).string();
}

}  // namespace troupe::world

// config_to_json(): a compiled node config printed through its schema, for
// `troupe-node --print-config` on boards that carry no JSON code of
// FlatBuffers (and the same text on the host).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "runtime/config_edit.h"
#include "runtime/config_schema.h"

namespace troupe {
namespace {

using config_schema::field_with_id;
using config_schema::object_at;
using config_schema::union_member;

class JsonWriter {
 public:
  explicit JsonWriter(const reflection::Schema& schema) : schema_(schema) {}

  std::string take() { return std::move(out_); }

  // `t` null: a table the config leaves out, shown with its defaults.
  void table(const reflection::Object& object, const flatbuffers::Table* t, int depth) {
    out_ += "{";
    bool first = true;
    for (uint32_t id = 0; id < object.fields()->size(); ++id) {
      const reflection::Field* f = field_with_id(object, id);
      if (f == nullptr || f->deprecated()) continue;
      const reflection::BaseType type = f->type()->base_type();
      const bool present = t != nullptr && t->CheckField(f->offset());
      const reflection::EnumVal* member =
          type == reflection::Union ? union_member(schema_, object, *f, t) : nullptr;
      // Numbers, switches and enums are shown with the value the node takes;
      // a driver type of none and absent strings, lists and tables are not.
      if (type == reflection::UType ? !present || t->GetField<uint8_t>(f->offset(), 0) == 0
                                    : !flatbuffers::IsScalar(type) && !present && member == nullptr) {
        continue;
      }
      out_ += first ? "\n" : ",\n";
      first = false;
      indent(depth + 1);
      quoted(f->name()->c_str());
      out_ += ": ";
      const uint8_t* at = present ? t->GetAddressOf(f->offset()) : nullptr;
      if (member != nullptr) {
        table(config_schema::member_object(schema_, *member),
              present ? t->GetPointer<const flatbuffers::Table*>(f->offset()) : nullptr, depth + 1);
      } else if (flatbuffers::IsScalar(type)) {
        scalar(*f, *f->type(), type, at);
      } else {
        value(*f->type(), type, at, depth + 1);
      }
    }
    out_ += "\n";
    indent(depth);
    out_ += "}";
  }

 private:
  // A non-scalar at `at` (the field's slot in its table, or a list's slot).
  void value(const reflection::Type& type, reflection::BaseType base, const uint8_t* at, int depth) {
    if (base == reflection::Obj && object_at(schema_, type.index()).is_struct()) {
      return structure(object_at(schema_, type.index()), at);
    }
    const uint8_t* p = at + flatbuffers::ReadScalar<flatbuffers::uoffset_t>(at);
    if (base == reflection::String) {
      const auto* s = reinterpret_cast<const flatbuffers::String*>(p);
      return quoted(s->c_str(), s->size());
    }
    if (base == reflection::Obj) {
      return table(object_at(schema_, type.index()), reinterpret_cast<const flatbuffers::Table*>(p), depth);
    }
    if (base != reflection::Vector) {
      out_ += "null";  // a list of unions: node configs have none
      return;
    }
    const flatbuffers::uoffset_t n = flatbuffers::ReadScalar<flatbuffers::uoffset_t>(p);
    const reflection::BaseType element = type.element();
    size_t size =
        flatbuffers::IsScalar(element) ? flatbuffers::GetTypeSize(element) : sizeof(flatbuffers::uoffset_t);
    if (element == reflection::Obj && object_at(schema_, type.index()).is_struct()) {
      size = size_t(object_at(schema_, type.index()).bytesize());
    }
    // Tables one a line; strings, numbers and small structs on one line.
    const bool lines = element == reflection::Obj && !object_at(schema_, type.index()).is_struct();
    out_ += "[";
    for (flatbuffers::uoffset_t i = 0; i < n; ++i) {
      const uint8_t* item = p + sizeof(flatbuffers::uoffset_t) + i * size;
      out_ += i == 0 ? "" : ",";
      if (lines) {
        out_ += "\n";
        indent(depth + 1);
      } else if (i > 0) {
        out_ += " ";
      }
      if (flatbuffers::IsScalar(element)) {
        scalar_bytes(type, element, item);
      } else {
        value(type, element, item, depth + 1);
      }
    }
    if (lines && n > 0) {
      out_ += "\n";
      indent(depth);
    }
    out_ += "]";
  }

  void structure(const reflection::Object& object, const uint8_t* at) {
    out_ += "{";
    bool first = true;
    for (uint32_t id = 0; id < object.fields()->size(); ++id) {
      const reflection::Field* f = field_with_id(object, id);
      if (f == nullptr) continue;
      out_ += first ? " " : ", ";
      first = false;
      quoted(f->name()->c_str());
      out_ += ": ";
      if (f->type()->base_type() == reflection::Obj) {
        structure(object_at(schema_, f->type()->index()), at + f->offset());
      } else {
        scalar_bytes(*f->type(), f->type()->base_type(), at + f->offset());
      }
    }
    out_ += " }";
  }

  // A table's scalar field: its bytes, or its default when absent.
  void scalar(const reflection::Field& f, const reflection::Type& type, reflection::BaseType base,
              const uint8_t* at) {
    if (at != nullptr) return scalar_bytes(type, base, at);
    if (flatbuffers::IsFloat(base)) return real(f.default_real(), base == reflection::Float);
    integer(type, base, f.default_integer());
  }

  void scalar_bytes(const reflection::Type& type, reflection::BaseType base, const uint8_t* at) {
    using flatbuffers::ReadScalar;
    switch (base) {
      case reflection::Float:
        return real(ReadScalar<float>(at), true);
      case reflection::Double:
        return real(ReadScalar<double>(at), false);
      case reflection::Byte:
        return integer(type, base, ReadScalar<int8_t>(at));
      case reflection::Short:
        return integer(type, base, ReadScalar<int16_t>(at));
      case reflection::Int:
        return integer(type, base, ReadScalar<int32_t>(at));
      case reflection::Long:
        return integer(type, base, ReadScalar<int64_t>(at));
      case reflection::UShort:
        return integer(type, base, ReadScalar<uint16_t>(at));
      case reflection::UInt:
        return integer(type, base, ReadScalar<uint32_t>(at));
      case reflection::ULong:
        return integer(type, base, int64_t(ReadScalar<uint64_t>(at)));
      default:
        return integer(type, base, ReadScalar<uint8_t>(at));  // UType, Bool, UByte
    }
  }

  void integer(const reflection::Type& type, reflection::BaseType base, int64_t v) {
    if (base == reflection::Bool) {
      out_ += v != 0 ? "true" : "false";
      return;
    }
    if (type.index() >= 0) {  // an enum, or a union's type: by name
      for (const reflection::EnumVal* e : *schema_.enums()->Get(uint32_t(type.index()))->values()) {
        if (e->value() == v) return quoted(e->name()->c_str());
      }
    }
    char text[24];
    if (base == reflection::ULong) {
      snprintf(text, sizeof text, "%llu", static_cast<unsigned long long>(v));
    } else {
      snprintf(text, sizeof text, "%lld", static_cast<long long>(v));
    }
    out_ += text;
  }

  // The shortest text that reads back as the same float or double.
  void real(double v, bool is_float) {
    char text[32];
    for (int digits = is_float ? 6 : 15; digits <= 17; ++digits) {
      snprintf(text, sizeof text, "%.*g", digits, v);
      const double back = strtod(text, nullptr);
      if (is_float ? float(back) == float(v) : back == v) break;
    }
    out_ += text;
  }

  void quoted(const char* s, size_t n = std::string::npos) {
    if (n == std::string::npos) n = strlen(s);
    out_ += '"';
    for (size_t i = 0; i < n; ++i) {
      const unsigned char c = static_cast<unsigned char>(s[i]);
      if (c == '"' || c == '\\') {
        out_ += '\\';
        out_ += char(c);
      } else if (c < 0x20) {
        char esc[8];
        snprintf(esc, sizeof esc, "\\u%04x", c);
        out_ += esc;
      } else {
        out_ += char(c);
      }
    }
    out_ += '"';
  }

  void indent(int depth) { out_.append(size_t(depth) * 2, ' '); }

  const reflection::Schema& schema_;
  std::string out_;
};

}  // namespace

std::string config_to_json(const reflection::Schema& schema, const uint8_t* config) {
  JsonWriter json(schema);
  json.table(*schema.root_table(), flatbuffers::GetAnyRoot(config), 0);
  std::string text = json.take();
  text += "\n";
  return text;
}

}  // namespace troupe

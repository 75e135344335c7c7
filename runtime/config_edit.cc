// set_config_value(): one value of a compiled node config changed, checked
// against the schema. A FlatBuffer cannot grow in place (a longer serial
// port name would not fit), so the config is copied field by field through
// the schema into a new buffer, with the one value replaced.
#include "runtime/config_edit.h"

#include <cerrno>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "runtime/config_schema.h"

namespace troupe {
namespace {

using config_schema::field_with_id;
using config_schema::object_at;
using config_schema::union_member;
using flatbuffers::uoffset_t;

// Which table of the config the copy is in: an edit lands in the root
// (a node setting) or in the options table of one driver instance.
enum class Place : uint8_t { Root, Instance, Options, Other };
struct Where {
  Place place = Place::Other;
  uint32_t instance = 0;
  bool operator==(const Where&) const = default;
};

struct Edit {
  Where where;
  const reflection::Field* field = nullptr;
  uint8_t scalar[8] = {};  // the new value, little-endian, as the buffer holds it
  std::string text;        // the new value of a string field
};

class Copier {
 public:
  Copier(const reflection::Schema& schema, const Edit& edit) : schema_(schema), edit_(edit) {}

  std::vector<uint8_t> copy(const uint8_t* config) {
    uoffset_t root = table(*schema_.root_table(), flatbuffers::GetAnyRoot(config), Where{Place::Root});
    const char* ident = schema_.file_ident() ? schema_.file_ident()->c_str() : nullptr;
    fbb_.Finish(flatbuffers::Offset<void>(root), ident != nullptr && *ident != '\0' ? ident : nullptr);
    return {fbb_.GetBufferPointer(), fbb_.GetBufferPointer() + fbb_.GetSize()};
  }

 private:
  // `t` may be null: a table the config leaves out that the edit creates.
  uoffset_t table(const reflection::Object& object, const flatbuffers::Table* t, Where where) {
    const auto& fields = *object.fields();
    const reflection::Field* edited = where == edit_.where ? edit_.field : nullptr;
    // A table's strings, vectors and sub-tables go into the buffer before it.
    std::vector<uoffset_t> children(fields.size(), 0);
    for (uoffset_t k = 0; k < fields.size(); ++k) {
      const reflection::Field& f = *fields[k];
      const reflection::BaseType type = f.type()->base_type();
      const uint8_t* p =
          t != nullptr && !flatbuffers::IsScalar(type) ? t->GetPointer<const uint8_t*>(f.offset()) : nullptr;
      if (&f == edited && type == reflection::String) {
        children[k] = fbb_.CreateString(edit_.text).o;
      } else if (type == reflection::String && p != nullptr) {
        children[k] = fbb_.CreateString(reinterpret_cast<const flatbuffers::String*>(p)).o;
      } else if (type == reflection::Vector && p != nullptr) {
        children[k] = vector(f, p, where);
      } else if (type == reflection::Obj && p != nullptr &&
                 !object_at(schema_, f.type()->index()).is_struct()) {
        children[k] = table(object_at(schema_, f.type()->index()),
                            reinterpret_cast<const flatbuffers::Table*>(p), Where{});
      } else if (type == reflection::Union) {
        // An instance's options: created when the config gives none and the
        // edit sets one of them.
        Where inner = where.place == Place::Instance ? Where{Place::Options, where.instance} : Where{};
        const reflection::EnumVal* member = union_member(schema_, object, f, t);
        if (member != nullptr && (p != nullptr || inner == edit_.where)) {
          children[k] = table(config_schema::member_object(schema_, *member),
                              reinterpret_cast<const flatbuffers::Table*>(p), inner);
        }
      }
    }
    uoffset_t start = fbb_.StartTable();
    for (uoffset_t k = 0; k < fields.size(); ++k) {
      const reflection::Field& f = *fields[k];
      const reflection::BaseType type = f.type()->base_type();
      if (children[k] != 0) {
        fbb_.AddOffset(f.offset(), flatbuffers::Offset<void>(children[k]));
      } else if (&f == edited && flatbuffers::IsScalar(type)) {
        inline_bytes(f.offset(), edit_.scalar, flatbuffers::GetTypeSize(type),
                     flatbuffers::GetTypeSize(type));
      } else if (t != nullptr && t->CheckField(f.offset())) {
        if (flatbuffers::IsScalar(type)) {
          const size_t size = flatbuffers::GetTypeSize(type);
          inline_bytes(f.offset(), t->GetAddressOf(f.offset()), size, size);
        } else if (type == reflection::Obj && object_at(schema_, f.type()->index()).is_struct()) {
          const reflection::Object& s = object_at(schema_, f.type()->index());
          inline_bytes(f.offset(), t->GetAddressOf(f.offset()), size_t(s.bytesize()), size_t(s.minalign()));
        }
      }
    }
    return fbb_.EndTable(start);
  }

  // Scalars and structs are copied as the bytes they are: the buffer's byte
  // order is the wire's on every target.
  void inline_bytes(flatbuffers::voffset_t field, const uint8_t* bytes, size_t size, size_t align) {
    fbb_.Align(align);
    fbb_.PushBytes(bytes, size);
    fbb_.TrackField(field, fbb_.GetSize());
  }

  uoffset_t vector(const reflection::Field& f, const uint8_t* p, Where where) {
    const uoffset_t n = flatbuffers::ReadScalar<uoffset_t>(p);
    const uint8_t* data = p + sizeof(uoffset_t);
    const reflection::BaseType element = f.type()->element();
    auto at = [data](uoffset_t i) {
      const uint8_t* slot = data + i * sizeof(uoffset_t);
      return slot + flatbuffers::ReadScalar<uoffset_t>(slot);
    };
    if (element == reflection::String ||
        (element == reflection::Obj && !object_at(schema_, f.type()->index()).is_struct())) {
      std::vector<flatbuffers::Offset<void>> items(n);
      for (uoffset_t i = 0; i < n; ++i) {
        if (element == reflection::String) {
          items[i] = fbb_.CreateString(reinterpret_cast<const flatbuffers::String*>(at(i))).Union();
        } else {
          // The root's list of tables is its driver instances.
          Where inner = where.place == Place::Root ? Where{Place::Instance, i} : Where{};
          items[i] =
              flatbuffers::Offset<void>(table(object_at(schema_, f.type()->index()),
                                              reinterpret_cast<const flatbuffers::Table*>(at(i)), inner));
        }
      }
      return fbb_.CreateVector(items).o;
    }
    size_t size = 0, align = 0;
    if (element == reflection::Obj) {
      const reflection::Object& s = object_at(schema_, f.type()->index());
      size = size_t(s.bytesize());
      align = size_t(s.minalign());
    } else if (flatbuffers::IsScalar(element)) {
      size = align = flatbuffers::GetTypeSize(element);
    } else {
      return 0;  // a list of unions: node configs have none
    }
    fbb_.StartVector(n * size, 1);
    fbb_.PreAlign(n * size, align);
    fbb_.PushBytes(data, n * size);
    return fbb_.EndVector(n);
  }

  const reflection::Schema& schema_;
  const Edit& edit_;
  flatbuffers::FlatBufferBuilder fbb_{1024};
};

// Sets `error` from a printf format; false, for `return say(...)`.
bool say(std::string& error, const char* format, ...) __attribute__((format(printf, 2, 3)));
bool say(std::string& error, const char* format, ...) {
  char text[1024];
  va_list args;
  va_start(args, format);
  vsnprintf(text, sizeof text, format, args);
  va_end(args);
  error = text;
  return false;
}

// "a, b, c": the names a mistake could have meant.
std::string names_of(const reflection::Object& object) {
  std::string names;
  for (uint32_t id = 0; id < object.fields()->size(); ++id) {
    const reflection::Field* f = field_with_id(object, id);
    // A union's type is set with the union, in the file.
    if (f == nullptr || f->deprecated() || f->type()->base_type() == reflection::UType) continue;
    names += names.empty() ? "" : ", ";
    names += f->name()->c_str();
  }
  return names;
}

// The range of each integer type, for the check and the message.
bool integer_range(reflection::BaseType type, int64_t& min, uint64_t& max) {
  if (type < reflection::Byte || type > reflection::ULong) return false;
  const int bits = 8 << ((type - reflection::Byte) / 2);
  const bool is_signed = (type - reflection::Byte) % 2 == 0;
  max = bits == 64 ? (is_signed ? uint64_t(INT64_MAX) : UINT64_MAX) : (uint64_t(1) << (bits - is_signed)) - 1;
  min = is_signed ? -int64_t(max) - 1 : 0;
  return true;
}

// The value text as the field's type, into edit.scalar or edit.text; false
// with `error` when it is not one.
bool parse_value(const reflection::Schema& schema, const reflection::Field& f, const char* what,
                 const std::string& text, Edit& edit, std::string& error) {
  const reflection::BaseType type = f.type()->base_type();
  const char* s = text.c_str();
  char* end = const_cast<char*>(s);  // where the value's text stopped being one
  char kind[96];
  bool out_of_range = false;
  int64_t min = 0;
  uint64_t max = 0;
  errno = 0;
  if (type == reflection::String) {
    edit.text = text;
    return true;
  }
  if (type == reflection::Bool) {
    snprintf(kind, sizeof kind, "true or false");
    edit.scalar[0] = text == "true";
    end = const_cast<char*>(text == "true" || text == "false" ? s + text.size() : s);
  } else if (type == reflection::Float || type == reflection::Double) {
    const bool is_float = type == reflection::Float;
    snprintf(kind, sizeof kind, is_float ? "a finite 32-bit number (at most 3.4e38)" : "a finite number");
    const double v = strtod(s, &end);
    if (!std::isfinite(v)) end = const_cast<char*>(s);
    out_of_range = is_float && std::fabs(v) > 3.4028234663852886e38;
    if (is_float) {
      flatbuffers::WriteScalar(edit.scalar, float(v));
    } else {
      flatbuffers::WriteScalar(edit.scalar, v);
    }
  } else if (!integer_range(type, min, max)) {
    return say(error, "%s is %s: change it in the config file", what,
               type == reflection::Vector  ? "a list"
               : type == reflection::UType ? "a driver type"
                                           : "a table");
  } else {
    int64_t value = 0;
    const reflection::Enum* named =
        f.type()->index() >= 0 ? schema.enums()->Get(uint32_t(f.type()->index())) : nullptr;
    if (named != nullptr) {
      std::string names;
      for (const reflection::EnumVal* v : *named->values()) {
        if (v->name()->str() == text) {
          value = v->value();
          end = const_cast<char*>(s + text.size());
        }
        names += names.empty() ? "" : ", ";
        names += v->name()->c_str();
      }
      snprintf(kind, sizeof kind, "one of %s", names.c_str());
    } else {
      snprintf(kind, sizeof kind, "an integer from %lld to %llu", static_cast<long long>(min),
               static_cast<unsigned long long>(max));
      // strtoull takes "-1" for a huge number: the sign is looked at here.
      if (text.starts_with('-')) {
        value = strtoll(s, &end, 10);
        out_of_range = value < min;
      } else {
        const uint64_t u = strtoull(s, &end, 10);
        out_of_range = u > max;
        value = int64_t(u);
      }
      out_of_range = out_of_range || errno == ERANGE;
      if (!std::isdigit(uint8_t(text[text.starts_with('-') || text.starts_with('+')])))
        end = const_cast<char*>(s);
    }
    switch (flatbuffers::GetTypeSize(type)) {
      case 1:
        flatbuffers::WriteScalar(edit.scalar, uint8_t(value));
        break;
      case 2:
        flatbuffers::WriteScalar(edit.scalar, uint16_t(value));
        break;
      case 4:
        flatbuffers::WriteScalar(edit.scalar, uint32_t(value));
        break;
      default:
        flatbuffers::WriteScalar(edit.scalar, uint64_t(value));
        break;
    }
  }
  if (end == s || *end != '\0') return say(error, "'%s' is not a value of %s, which is %s", s, what, kind);
  if (out_of_range) return say(error, "'%s' is out of range for %s, which is %s", s, what, kind);
  return true;
}

// Which driver instance INSTANCE names: its "name", else its driver type.
bool find_instance(const reflection::Schema& schema, const flatbuffers::Table& root, const std::string& name,
                   Edit& edit, const reflection::Object*& options, std::string& error) {
  const reflection::Field* drivers = schema.root_table()->fields()->LookupByKey("drivers");
  const reflection::Object& instance = object_at(schema, drivers->type()->index());
  const reflection::Field* name_field = instance.fields()->LookupByKey("name");
  const reflection::Field* union_field = instance.fields()->LookupByKey("driver");
  const auto* list =
      root.GetPointer<const flatbuffers::Vector<flatbuffers::Offset<flatbuffers::Table>>*>(drivers->offset());
  std::string names;
  bool found = false;
  for (uoffset_t i = 0; list != nullptr && i < list->size(); ++i) {
    const flatbuffers::Table* inst = list->Get(i);
    const reflection::EnumVal* member = union_member(schema, instance, *union_field, inst);
    const flatbuffers::String* given = inst->GetPointer<const flatbuffers::String*>(name_field->offset());
    const char* inst_name = given ? given->c_str() : member ? member->name()->c_str() : "?";
    names += names.empty() ? "" : ", ";
    names += inst_name;
    if (name != inst_name) continue;
    if (found) {
      return say(
          error,
          "'%s' names more than one driver instance (drivers[%u] and drivers[%u]): give them \"name\"s "
          "of their own in the config",
          name.c_str(), unsigned(edit.where.instance), unsigned(i));
    }
    if (member == nullptr) return say(error, "drivers[%u] has no driver type this board knows", unsigned(i));
    found = true;
    edit.where = Where{Place::Options, i};
    options = &config_schema::member_object(schema, *member);
  }
  if (!found) {
    return say(error, "no driver instance '%s' in the config; its instances: %s", name.c_str(),
               names.empty() ? "none" : names.c_str());
  }
  return true;
}

}  // namespace

bool set_config_value(const reflection::Schema& schema, std::vector<uint8_t>& config,
                      std::string_view assignment, std::string& error) {
  const size_t eq = assignment.find('=');
  if (eq == std::string_view::npos || eq == 0) {
    return say(error,
               "expected INSTANCE.KEY=VALUE (a driver instance's option) or KEY=VALUE (a node setting)");
  }
  const std::string path(assignment.substr(0, eq));
  const size_t dot = path.rfind('.');
  const std::string key = path.substr(dot + 1);  // npos + 1: all of it
  Edit edit;
  edit.where = Where{Place::Root};
  const reflection::Object* object = schema.root_table();
  if (dot != std::string::npos && !find_instance(schema, *flatbuffers::GetAnyRoot(config.data()),
                                                 path.substr(0, dot), edit, object, error)) {
    return false;
  }
  const reflection::Field* field = object->fields()->LookupByKey(key.c_str());
  if (field == nullptr || field->deprecated()) {
    if (dot == std::string::npos) {
      return say(error,
                 "no node setting '%s' (a driver instance's option is INSTANCE.KEY); node settings: %s",
                 key.c_str(), names_of(*object).c_str());
    }
    return say(error, "%.*s has no option '%s'; its options: %s", int(dot), path.c_str(), key.c_str(),
               names_of(*object).c_str());
  }
  if (!parse_value(schema, *field, path.c_str(), std::string(assignment.substr(eq + 1)), edit, error))
    return false;
  edit.field = field;
  config = Copier(schema, edit).copy(config.data());
  return true;
}

}  // namespace troupe

// What config_edit.cc and config_print.cc both ask of a binary schema.
#pragma once

#include "flatbuffers/reflection.h"

namespace troupe::config_schema {

/// The field of `object` with id `id` (the schema keeps fields by name;
/// configs are written and shown in id order), or nullptr.
inline const reflection::Field* field_with_id(const reflection::Object& object, uint32_t id) {
  for (const reflection::Field* f : *object.fields()) {
    if (f->id() == id) return f;
  }
  return nullptr;
}

/// The member a union field holds in `table` (by the type field before it,
/// "<name>_type"), or nullptr for none or a type this schema does not know.
/// Its name is the driver type; its union_type() the options table.
inline const reflection::EnumVal* union_member(const reflection::Schema& schema,
                                               const reflection::Object& object,
                                               const reflection::Field& field,
                                               const flatbuffers::Table* table) {
  const reflection::Field* type_field = field_with_id(object, field.id() - 1u);
  if (table == nullptr || type_field == nullptr) return nullptr;
  const int64_t type = table->GetField<uint8_t>(type_field->offset(), 0);
  for (const reflection::EnumVal* v : *schema.enums()->Get(uint32_t(field.type()->index()))->values()) {
    if (v->value() == type && type != 0 && v->union_type() != nullptr) return v;
  }
  return nullptr;
}

/// An object of the schema by its index (Type::index of an Obj field).
inline const reflection::Object& object_at(const reflection::Schema& schema, int32_t index) {
  return *schema.objects()->Get(uint32_t(index));
}

/// A union member's table type.
inline const reflection::Object& member_object(const reflection::Schema& schema,
                                               const reflection::EnumVal& member) {
  return object_at(schema, member.union_type()->index());
}

}  // namespace troupe::config_schema

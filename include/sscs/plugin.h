/* sscs plugin ABI, version 1: the C interface between sscs and a plugin (a shared object in a
 * plugin folder). Only C types cross it: no C++ types, no exceptions (plugin.hpp wraps it for
 * C++ authors and catches exceptions before they reach sscs).
 *
 * A plugin exports two functions:
 *   uint32_t sscs_plugin_abi_version(void);               -- returns SSCS_PLUGIN_ABI_VERSION
 *   int sscs_plugin_register(const sscs_host* host);      -- registers its classes; 0 on success
 * sscs calls sscs_plugin_abi_version first and refuses a plugin built for another version.
 *
 * Object types (the report's object sub-classes): a plugin declares a type like a type-library
 * file does -- its name, the type it extends, its attributes (the report's getAttributeNum,
 * getAttributeNames and getAttributeRef: attribute_count, attributes[i].name and the attribute
 * itself) and its geometry as shapes whose sizes are expressions over the attributes. Vaults use
 * it like any library type.
 *
 * Constraint classes (the report's "functional constraints"): a `plugin` constraint in a vault
 * names a class, the participating attributes (references such as Room1.height) and free-form
 * args; sscs passes the attribute values (in the file units: m, deg, kg, s) and the args as JSON
 * to the class's check, which answers pass or fail, a margin (how far from violation, positive
 * when satisfied, in `unit`) and a message.
 */
#ifndef SSCS_PLUGIN_H
#define SSCS_PLUGIN_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define SSCS_PLUGIN_ABI_VERSION 1u

#if defined(__GNUC__)
#define SSCS_PLUGIN_EXPORT __attribute__((visibility("default")))
#else
#define SSCS_PLUGIN_EXPORT
#endif

/* What a check answers. sscs zero-fills it before the call. */
typedef struct sscs_check_result {
  int pass;            /* 1: satisfied, 0: violated */
  double margin;       /* positive when satisfied; a NaN margin is reported as an error */
  char unit[16];       /* the margin's unit ("m", "deg", "" for a plain number) */
  char message[512];   /* what the report prints; on an error, what went wrong */
} sscs_check_result;

/* One participating attribute, in the order the vault lists them. */
typedef struct sscs_value {
  const char* ref;     /* as written: "Room1.height" */
  double value;        /* in the file unit of its dimension */
  const char* unit;    /* "m", "deg", "kg", "s" or "" */
} sscs_value;

/* Returns 0 when it could evaluate (result->pass says the outcome), nonzero on an error (with
 * result->message saying why): then the constraint's status is `error`. */
typedef int (*sscs_check_fn)(void* user, const sscs_value* values, size_t count, const char* args_json,
                             sscs_check_result* result);

typedef struct sscs_constraint_class {
  const char* name;          /* the `class:` a vault names; letters, digits, _ and - */
  const char* description;
  size_t min_values;         /* how many attributes it needs ... */
  size_t max_values;         /* ... (SIZE_MAX: any number) */
  sscs_check_fn check;
  void* user;                /* passed back to check */
} sscs_constraint_class;

/* One attribute of an object type. Strings are written as in a type file: numbers in the file
 * unit of the type's dimension (m, deg, kg, s) or with a unit ("0.6 m", "90 deg"). NULL: absent. */
typedef struct sscs_attribute {
  const char* name;
  const char* type;          /* length angle mass time number integer boolean string enum */
  const char* default_value; /* NULL: the attribute is required */
  const char* min;
  const char* max;
  const char* values;        /* enum only: the values, comma-separated ("open,closed") */
  const char* description;
} sscs_attribute;

/* One shape of an object type's geometry, in the object's frame. Sizes and placements are
 * expressions over the type's attributes ("diameter/2"); NULL placements are 0. */
typedef struct sscs_shape {
  const char* kind;          /* box, cylinder, sphere or mesh */
  const char* size[3];       /* box */
  const char* radius;        /* cylinder, sphere */
  const char* length;        /* cylinder (along local z) */
  const char* file;          /* mesh: relative to the plugin's folder */
  const char* scale[3];      /* mesh; NULL: 1 */
  const char* xyz[3];
  const char* rpy[3];        /* degrees */
} sscs_shape;

/* A named frame of an object type (a target for reach and move_to). */
typedef struct sscs_frame {
  const char* name;
  const char* xyz[3];
  const char* rpy[3];
} sscs_frame;

typedef struct sscs_object_type {
  const char* name;          /* the `type:` a vault names */
  const char* extends;       /* NULL or "object": the super-class; else a library or plugin type */
  const char* description;
  const char* color;         /* NULL or "#RRGGBB" */
  const sscs_attribute* attributes;
  size_t attribute_count;
  const sscs_shape* geometry;
  size_t shape_count;
  const sscs_frame* frames;
  size_t frame_count;
} sscs_object_type;

/* What sscs offers a registering plugin. `size` is sizeof(sscs_host) in the sscs that calls:
 * later versions only add members at the end. Strings are copied; they need not outlive the call. */
typedef struct sscs_host {
  uint32_t abi_version;
  uint32_t size;
  void* context;
  /* Returns 0, or nonzero when the class is rejected (a bad name, a name already taken). */
  int (*add_constraint_class)(void* context, const sscs_constraint_class* cls);
  /* Reports why registration fails (printed with the plugin's path). */
  void (*error)(void* context, const char* message);
  /* Returns 0, or nonzero when the type is rejected (invalid, or its name already taken by
   * another plugin; a name the type library also defines fails when a vault is compiled). */
  int (*add_object_type)(void* context, const sscs_object_type* type);
  /* Added after the first release (check `size` first): gives a type this plugin registered its mass, as a type
   * file's `mass:` does: a number (kg) or an expression over its attributes ("22 + fill_mass").
   * Without it the physics takes a `mass` attribute, else estimates from the bounds. Returns 0, or
   * nonzero when rejected (no such type of this plugin, an invalid expression). */
  int (*set_object_type_mass)(void* context, const char* type_name, const char* mass);
} sscs_host;

typedef uint32_t (*sscs_plugin_abi_version_fn)(void);
typedef int (*sscs_plugin_register_fn)(const sscs_host* host);

#ifdef __cplusplus
}
#endif

#endif /* SSCS_PLUGIN_H */

#pragma once
// Mitsuba 3 XML (scene `version` 2.x or 3.x) read through the Mitsuba 0.6 readers: the
// parameter names and plugin types of Mitsuba 3, as its plugins read them, mapped onto the
// 0.6 names those readers ask for (internal to src/scene). The mapping follows Mitsuba
// 3.9.1 (mitsuba-renderer/mitsuba3, August 2026): its XML parser (src/core/parser.cpp),
// the plugins' own parameter lists (src/bsdfs, src/emitters, src/films, src/integrators,
// src/rfilters, src/samplers, src/sensors, src/shapes, src/textures) and their base classes
// (src/render). Meanings Mitsuba 3 changed are applied by the readers where they read the
// parameter (look for `mitsuba3()`); docs/compatibility.md lists them. The .cpp file also
// holds the parser layer's checks that only a Mitsuba 3 file needs (plugins and colour
// forms Mitsuba 3 dropped).
#include <string>
#include <string_view>

namespace emlt::mitsuba {

// Whether a <scene version="..."> is Mitsuba 3's dialect: a major version of 2 or 3
// (Mitsuba 2 introduced the snake_case names; Mitsuba 3 reads 2.x files unchanged).
bool is_mitsuba3_version(std::string_view version);

// The key under which the 0.6 readers find a parameter `name` of the element `element`
// (<bsdf>, <shape> ...) of plugin `type`, given in a Mitsuba 3 file: "toWorld" for
// "to_world", "reflectance" for "reflectance", a name of Mitsuba 3's own that the readers
// ask for under that name ("to_uv", "raw"). Empty when Mitsuba 3 reads no such parameter
// there (a camelCase 0.6 name, a 0.6 parameter Mitsuba 3 dropped such as a bitmap's
// `gamma`): the caller keeps it out of the readers' reach, so it ends up reported as an
// unsupported parameter instead of being given its 0.6 meaning.
std::string mitsuba3_key(std::string_view element, std::string_view type, std::string_view name);

// Whether `type` is a plugin of Mitsuba 0.6 that the readers render but Mitsuba 3 no longer
// has (<bsdf type="phong">, <integrator type="bdpt"> ...): Mitsuba 3 refuses such a file.
bool mitsuba06_only_plugin(std::string_view element, std::string_view type);

}  // namespace emlt::mitsuba

#pragma once
namespace clsph {
// The library's version, "MAJOR.MINOR.PATCH".
const char* version();
}  // namespace clsph

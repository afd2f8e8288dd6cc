#pragma once
// The base file I/O (core/io, garmcap/io/file_io.h) under capture's names: whole-file reads,
// crash-safe writes and strict JSON field access for the rig reader. capture may not link drafts
// (docs/architecture.md), so both link the base library instead of keeping a copy each.

#include "garmcap/io/file_io.h"

namespace garmcap::capture {

using io::FileError;
using io::ParseError;
using io::readFile;
using io::readJsonFile;
using io::requireField;
using io::requireNumber;
using io::requireString;
using io::writeFileAtomic;
using io::writeJsonFile;

}  // namespace garmcap::capture

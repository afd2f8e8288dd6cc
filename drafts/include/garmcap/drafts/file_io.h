#pragma once
// The base file I/O (core/io, garmcap/io/file_io.h) under the names drafts and its users have
// always called it by: one implementation, one set of exception types for every module.

#include "garmcap/io/file_io.h"

namespace garmcap::drafts {

using io::FileError;
using io::ParseError;
using io::parseJson;
using io::readFile;
using io::readJsonFile;
using io::requireField;
using io::requireNumber;
using io::requireString;
using io::writeFileAtomic;
using io::writeJsonFile;

}  // namespace garmcap::drafts

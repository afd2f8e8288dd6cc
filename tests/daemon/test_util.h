#pragma once
// Helpers shared by the daemon's unit tests: temp folders.
#include "../common/temp_folder.h"

namespace garmcap::daemon::test {

/// A fresh folder under the system temp dir, removed with its contents at destruction.
using TempDir = garmcap::testing::TempFolder;

}  // namespace garmcap::daemon::test

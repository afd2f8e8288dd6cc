#include "garmcap/daemon/station_routes.h"

#include "garmcap/daemon/api_routes.h"
#include "garmcap/daemon/station.h"

namespace garmcap::daemon {

void addStationRoutes(Router& router, Station& station) {
  addApiRoutes(router, station);
  addReviewRoutes(router, station);
  addSettingsRoutes(router, station);
  addTapeRoutes(router, station);
  addExportRoutes(router, station);
}

}  // namespace garmcap::daemon

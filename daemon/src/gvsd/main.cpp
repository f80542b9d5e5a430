// gvsd: the ground velocity sensor daemon (see docs/daemon.md).
#include "gvs/daemon/app.hpp"

int main(int argc, char** argv) { return gvs::daemon::gvsd_main(argc, argv); }

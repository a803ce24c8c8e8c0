#pragma once
// SIGINT/SIGTERM set a flag that every Run() loop polls between handleTimeout calls, so a
// process always leaves through its normal path (flush, final STATUS, exit code).
namespace gyrocal::process {

void InstallStopHandlers();
bool StopRequested();
void RequestStop();  // for tests and for nodes that finish by themselves

}  // namespace gyrocal::process

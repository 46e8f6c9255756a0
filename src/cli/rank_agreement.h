#pragma once
// How `emlt render` fails under MPI (cluster.h). Each rank reads the scene, the reference
// and the checkpoint by itself and may fail alone (a file missing on one node). Every rank
// therefore meets the others once the setup is done: if any failed, all of them stop with
// the lowest failing rank's one-line error, printed once by rank 0. A failure after that
// point (memory, a full disk) would leave the other ranks waiting in a collective, so the
// failing rank prints its error and ends every rank with MPI_Abort: never a hang.
#include <string>

namespace emlt::cli {

// Called by every rank when its setup succeeded; throws emlt::Error (the failing rank's
// message) when another rank's did not.
void setup_succeeded();

// main's handling of an error on this rank: returns the message to print ("" when this rank
// prints nothing), or, for a failure during the render of a multi-rank run, prints it and
// ends every rank.
std::string settle_error(const std::string& message);

}  // namespace emlt::cli

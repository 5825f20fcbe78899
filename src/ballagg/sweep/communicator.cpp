#include "ballagg/sweep/communicator.hpp"

#include <cstdlib>

#include <mpi.h>

namespace ballagg {

bool launched_by_mpirun() {
  return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr || std::getenv("PMI_SIZE") != nullptr ||
         std::getenv("PMIX_RANK") != nullptr;
}

Communicator::Communicator() {
  if (!launched_by_mpirun()) return;
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  mpi_ = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

Communicator::~Communicator() {
  if (mpi_) MPI_Finalize();
}

void Communicator::barrier() const {
  if (mpi_) MPI_Barrier(MPI_COMM_WORLD);
}

long long Communicator::sum(long long v) const {
  if (!mpi_) return v;
  long long total = 0;
  MPI_Allreduce(&v, &total, 1, MPI_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
  return total;
}

}  // namespace ballagg

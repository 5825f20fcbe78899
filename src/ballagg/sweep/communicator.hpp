#pragma once
// The processes of a sweep: one, or the ranks of an MPI job when the program was started
// by mpirun (OpenMPI sets OMPI_COMM_WORLD_SIZE; other launchers PMI_SIZE or PMIX_RANK).
// Only the main thread calls MPI.
namespace ballagg {

class Communicator {
 public:
  // Initialises MPI if launched by mpirun; finalises it when destroyed.
  Communicator();
  ~Communicator();
  Communicator(const Communicator&) = delete;
  Communicator& operator=(const Communicator&) = delete;

  bool mpi() const { return mpi_; }
  int rank() const { return rank_; }
  int size() const { return size_; }
  void barrier() const;
  long long sum(long long v) const;  // over all ranks, known to all

 private:
  bool mpi_ = false;
  int rank_ = 0, size_ = 1;
};

// True when the environment says this process is a rank of an MPI job.
bool launched_by_mpirun();

}  // namespace ballagg

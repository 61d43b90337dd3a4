// The Newton method every problem class of the project shares (contact, beam/solid; FSI and
// multi-body contact next), in the shape of deal.II's step-44: each iteration reads as the
// algorithm,
//
//   linearize (K, r per field)  ->  converged?  ->  solve K dx = -r  ->  x += alpha dx,
//
// and the problem class supplies only its physics (NonlinearProblem). What lives here once:
//
// - Convergence per field. A problem's residual consists of fields in different units (forces
//   and weighted gaps in contact, forces and moments in beam/solid), so no single norm of the
//   whole residual is meaningful. Field f has converged when
//       ||r_f|| <= tol_abs,f    or    ||r_f|| <= tol_rel,f * max_k ||r_f^(k)||,
//   the maximum taken over this step's iterates so far (the first iterate's norm is the usual
//   reference, but a field can start at zero: contact constraints before the first contact) and
//   over the field's natural size where the problem gives one (Linearization::residual_scales). An
//   iterate is accepted when every field has converged, at least one update was made, and the
//   problem agrees (contact: the active set did not change in this linearization).
// - Failures, detected and named, never silently continued: a residual that is not finite, an
//   inverted element (the problem's assembly throws std::domain_error), divergence (a field grows
//   by more than the divergence factor over max(its largest norm since the first update,
//   tol_abs,f / tol_rel,f); neither the first update, which applies the load increment, nor the
//   iterate after a change of the problem's state (an active-set change adds constraints) is
//   judged, since either may raise a field from zero to ordinary values), no convergence
//   within the maximum
//   number of iterations, and a linear solve that failed (GMRES broke down, or stopped with a true
//   residual above the accepted fraction of both ||b|| and the step's first residual). The result says which; the step driver
//   (step_driver.h) then cuts the load/time step.
// - Optional backtracking line search on the scaled merit function
//       phi(x) = sum_f (||r_f(x)|| / s_f)^2,   s_f = max(max_k ||r_f^(k)||, tol_abs,f):
//   after an update the step length is halved while phi does not decrease, up to a given number
//   of times (the last trial is kept: a semi-smooth Newton step need not decrease phi).
// - The log line of every iterate (residual per field, the problem's own fields, the linear
//   solve's report) and the console table, and the timers of assembly, preconditioner set-up
//   and linear solve.
#pragma once

#include "common/run_output.h"

#include "block_system.h"
#include "krylov_solver.h"
#include "presets.h"
#include "types.h"

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>

#include <mpi.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <map>
#include <ostream>
#include <set>
#include <string>
#include <vector>

namespace physics
{
  /// Tolerances of one field's residual norm.
  struct FieldTolerance
  {
    double absolute = 1e-12;
    double relative = 1e-8;
  };

  enum class PreconditionerReuse
  {
    none,
    whole,
    transfers
  };

  struct NewtonSettings
  {
    int                         max_iterations = 30;
    std::vector<FieldTolerance> tolerances; ///< per field, in the problem's order
    /// A field whose norm exceeds this factor times max(its largest norm since the first update
    /// and the last active-set change, tol_abs / tol_rel) has diverged.
    double divergence_factor = 1e6;
    bool   line_search       = false;
    int    line_search_steps = 4; ///< halvings of the step length at most
    /// An unconverged GMRES solve is still accepted (inexact Newton) when its true residual is
    /// at most this times ||b||, or this times the step's first Newton residual; above both
    /// the solve has failed.
    double accepted_linear_residual = 1e-3;
    /// What of a Newton step's preconditioner the next Newton steps of the same solve keep
    /// while the problem's state_signature() is the one it was built for: nothing, the whole
    /// preconditioner, or the transfers of its hierarchy (set up again on the new matrix,
    /// BlockPreconditioner::refresh). An unconverged solve with a kept one is repeated with a
    /// fresh one.
    PreconditionerReuse reuse_preconditioner = PreconditionerReuse::none;
    /// Testing the failure handling: these linear solves (counted from 1 over the solver's life)
    /// are reported as failed after they ran.
    std::set<int> injected_failures;
    /// Write every Newton system to `export_directory`/<prefix>-newtonN (BlockSystem format).
    bool        export_systems = false;
    std::string export_directory;
    /// Write the aggregates of every Newton step's AMG hierarchy to
    /// `aggregates_directory`/<prefix>-newtonN.pvtu (multigrid/aggregate_export.h).
    bool        export_aggregates = false;
    std::string aggregates_directory;
  };

  /// What the problem hands over at each iterate.
  struct Linearization
  {
    /// K dx = -r with its block structure, near-nullspaces and interface maps.
    const multigrid::BlockSystem* system = nullptr;
    /// ||r_f|| per field (the problem's field order), of the residual as assembled.
    std::vector<double> residual_norms;
    /// Optional natural size of each field's residual (empty, or 0 for a field: none): the
    /// relative tolerance then also counts against it. Contact constraints C_j = lambda_n,j -
    /// max(0, lambda_n,j - c_n g_j / w_j) are measured against the multipliers themselves, so a
    /// constraint residual that is round-off of the contact pressures counts as converged even
    /// when the step never moved the constraints (a patch test starts in contact).
    std::vector<double> residual_scales;
  };

  /// The physics of one load/time step's nonlinear problem.
  class NonlinearProblem
  {
  public:
    virtual ~NonlinearProblem() = default;

    /// Names of the residual fields, e.g. {"displacement", "contact"}; the order of the norms.
    virtual std::vector<std::string> field_names() const = 0;
    /// Assembles the Newton system at the current iterate (`iteration` counts from 0 in each
    /// step). May throw std::domain_error for an inverted element.
    virtual Linearization linearize(int iteration) = 0;
    /// May the current iterate be accepted (in addition to the field tolerances)?
    virtual bool may_converge() const { return true; }
    /// A fingerprint of the problem's discrete state at the current iterate (contact: the active
    /// set), the same on every rank; 0 if the problem has none. A state that comes back after
    /// others in one step without the residual having halved since its last visit is a cycle of
    /// the semi-smooth Newton method (near a solution the Newton system depends on the state and
    /// hardly on anything else, so the iteration would only repeat itself): the solver stops the
    /// step with a failure, so the step driver cuts it at once instead of after the iteration budget.
    virtual std::uint64_t state_signature() const { return 0; }
    /// x += dx, dx on the full map of the last linearization's system (the Newton update; rows
    /// with prescribed values may go to their targets).
    virtual void update(const multigrid::MultiVector& dx) = 0;
    /// Line search: the last update becomes `step_length` times its Newton direction (prescribed
    /// values stay at their targets). Called after further linearizations, so the problem keeps
    /// the direction in its own numbering.
    virtual void set_update_length(double step_length) = 0;
    /// The problem's own fields of the current iterate: log entries and console columns
    /// (under console_header()).
    virtual void describe(JsonLinesLog::Line& /*line*/, std::ostream& /*console*/) const {}
    virtual std::string console_header() const { return ""; }
  };

  struct NewtonResult
  {
    bool                converged  = false;
    int                 iterations = 0;        ///< updates made
    std::string         failure;               ///< why it did not converge (empty if it did)
    std::vector<double> residuals;             ///< sqrt(sum_f ||r_f||^2) per iterate (summaries)
    std::vector<int>    linear_iterations;     ///< per solve
    double              setup_seconds = 0, solve_seconds = 0;
  };

  class NewtonSolver
  {
  public:
    /// `timer` gets the sections "assembly", "preconditioner setup" and "linear solve".
    NewtonSolver(NewtonSettings settings, multigrid::Preset preset, multigrid::SolveOptions options,
                 JsonLinesLog& log, dealii::ConditionalOStream& console, dealii::TimerOutput& timer, MPI_Comm comm);

    /// Prints the console table's header for `problem`'s fields.
    void print_header(const NonlinearProblem& problem) const;

    /// Newton iterations from the problem's current state. `step_fields` adds the caller's
    /// entries (step number, time) to every log line; `export_prefix` names exported systems.
    NewtonResult solve(NonlinearProblem& problem, const std::function<void(JsonLinesLog::Line&)>& step_fields,
                       const std::string& export_prefix);

    const NewtonSettings& settings() const { return settings_; }
    MPI_Comm              communicator() const { return comm_; }
    /// Linear solves so far (the count injected failures refer to; a restart continues it).
    int  solves() const { return solves_; }
    void set_solves(int n) { solves_ = n; }

  private:
    /// Per-field convergence of `norms` against `reference` (largest norms of this step).
    bool fields_converged(const std::vector<double>& norms, const std::vector<double>& reference) const;
    using StatesSeen = std::map<std::uint64_t, std::pair<int, double>>;
    /// "" or why the step stops: `state` (NonlinearProblem::state_signature) differs from the
    /// last iterate's but was seen earlier in this step at a residual not twice as large (a cycle
    /// of the active-set iteration). `seen`: state -> (iteration, residual) of its last visit.
    static std::string state_cycle(std::uint64_t state, int iteration, double residual, StatesSeen& seen,
                                   std::uint64_t& last);
    /// Why the iterate cannot go on (empty if it can): non-finite residuals, or residuals that
    /// diverged from `reference` (empty: not judged).
    std::string residual_failure(const std::vector<double>& norms, const std::vector<double>& reference,
                                 const std::vector<std::string>& names) const;
    /// The norm that divergence of a field is measured against: max(reference, tol_abs / tol_rel).
    double divergence_scale(double reference, std::size_t field) const;
    double merit(const std::vector<double>& norms, const std::vector<double>& reference) const;
    /// Preconditioner set-up and GMRES on the system; logs the solve. Returns the failure
    /// message of a failed solve (empty if usable). A non-empty `aggregates_path` writes the
    /// hierarchy's aggregates there (.pvtu).
    std::string solve_linear(const multigrid::BlockSystem& system, multigrid::MultiVector& dx,
                             double step_residual, JsonLinesLog::Line& line, NewtonResult& result,
                             const std::string& aggregates_path, std::uint64_t state);
    /// Sets up a fresh preconditioner for `system` (kept in preconditioner_ with `state`);
    /// returns "" or the failure message of a set-up that failed.
    std::string build_preconditioner(const multigrid::BlockSystem& system, const std::string& aggregates_path,
                                     std::uint64_t state);
    /// Sets the kept preconditioner up again for `system` with its kept transfers; false where
    /// that is not possible (BlockPreconditioner::refresh) or it failed (then there is none).
    bool                  refresh_preconditioner(const multigrid::BlockSystem& system);
    const FieldTolerance& tolerance(std::size_t field) const;

    NewtonSettings              settings_;
    multigrid::Preset           preset_;
    multigrid::SolveOptions     options_;
    JsonLinesLog&               log_;
    dealii::ConditionalOStream& console_;
    dealii::TimerOutput&        timer_;
    MPI_Comm                    comm_;
    FieldTolerance              default_tolerance_;
    int                         solves_ = 0; ///< linear solves so far (injected failures)
    /// The preconditioner of the last solve and the problem state it was built for (reused
    /// within one Newton solve only: NewtonSettings::reuse_preconditioner).
    std::unique_ptr<multigrid::BlockPreconditioner> preconditioner_;
    std::uint64_t                                   preconditioner_state_ = 0;
    bool level_smoother_checked_ = false; ///< SetupOptions::check_level_smoother done once
  };
} // namespace physics

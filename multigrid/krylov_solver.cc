#include "krylov_solver.h"

#include "temporary_files.h"

#include <Tpetra_MultiVector.hpp>
#include <Tpetra_Operator.hpp>
#include <Xpetra_TpetraMultiVector.hpp>
#include <Xpetra_CrsMatrixWrap.hpp>

#include <BelosPseudoBlockGmresSolMgr.hpp>
#include <BelosStatusTestCombo.hpp>
#include <BelosXpetraAdapter.hpp>
#include <BelosXpetraStatusTestGenResSubNorm.hpp>

#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_Time.hpp>
#include <Xpetra_BlockedCrsMatrix.hpp>
#include <Xpetra_MultiVectorFactory.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace multigrid
{
  namespace
  {
    using MV = MultiVector;
    using OP = Belos::OperatorT<MV>;

    /// VmHWM of /proc/self/status in MB (the process's peak resident set); 0 if unreadable.
    /// (The multigrid layer does not see deal.II's Utilities::System::get_memory_stats, which
    /// the physics layer uses for the same number.)
    double peak_resident_mb()
    {
      std::ifstream status("/proc/self/status");
      std::string   line;
      while (std::getline(status, line))
        if (line.rfind("VmHWM:", 0) == 0)
          return std::stod(line.substr(6)) / 1024.0; // the line reads "VmHWM:   123456 kB"
      return 0.0;
    }

    /// Records GMRES's implicit residual norm after every iteration; never stops the solver.
    class ResidualHistory : public Belos::StatusTest<SC, MV, OP>
    {
    public:
      Belos::StatusType checkStatus(Belos::Iteration<SC, MV, OP>* solver) override
      {
        std::vector<double> norms(1, 0.0);
        solver->getNativeResiduals(&norms);
        if (solver->getNumIters() > static_cast<int>(history.size()))
          history.push_back(norms[0]);
        else if (!history.empty())
          history.back() = norms[0];
        return Belos::Failed;
      }
      Belos::StatusType   getStatus() const override { return Belos::Failed; }
      void                reset() override {}
      void                print(std::ostream&, int) const override {}
      std::vector<double> history;
    };

    std::string json_number(double v)
    {
      if (!std::isfinite(v))
        return "null";
      std::ostringstream s;
      s << std::setprecision(6) << v;
      return s.str();
    }

    std::string json_string(const std::string& v)
    {
      std::string out = "\"";
      for (char c : v)
        {
          if (c == '"' || c == '\\')
            out += '\\';
          out += c;
        }
      return out + "\"";
    }
  } // namespace

  SolveReport solve(const BlockSystem& system, const BlockPreconditioner& preconditioner, MultiVector& x,
                    const SolveOptions& options)
  {
    SolveReport report;
    report.options        = options;
    report.preconditioner = preconditioner.info();
    report.global_size    = system.global_size();
    report.ranks          = system.comm()->getSize();
    for (std::size_t k = 0; k < system.n_blocks(); ++k)
      report.block_names.push_back(system.block(k).name);

    // The blocked operator is needed by the per-block status tests (they split the residual with
    // its map extractor); otherwise the merged matrix applies faster.
    RCP<Xpetra::Operator<SC, LO, GO, NO>> A =
        options.per_block
            ? Teuchos::rcp_dynamic_cast<Xpetra::Operator<SC, LO, GO, NO>>(system.blocked_matrix())
            : Teuchos::rcp_dynamic_cast<Xpetra::Operator<SC, LO, GO, NO>>(system.merged_matrix());
    auto belos_A = Teuchos::rcp(new Belos::XpetraOp<SC, LO, GO, NO>(A));
    auto belos_M = Teuchos::rcp(new Belos::XpetraOp<SC, LO, GO, NO>(preconditioner.op()));
    x.putScalar(0.0);
    auto problem =
        Teuchos::rcp(new Belos::LinearProblem<SC, MV, OP>(belos_A, Teuchos::rcpFromRef(x), system.rhs()));
    problem->setRightPrec(belos_M);
    problem->setProblem();

    auto params = Teuchos::rcp(new Teuchos::ParameterList());
    params->set("Convergence Tolerance", options.tolerance);
    params->set("Maximum Iterations", options.max_iterations);
    params->set("Num Blocks", options.restart);
    params->set("Maximum Restarts", options.max_iterations / std::max(options.restart, 1) + 1);
    params->set("Verbosity", Belos::Errors);
    Belos::PseudoBlockGmresSolMgr<SC, MV, OP> gmres(problem, params);

    auto history = Teuchos::rcp(new ResidualHistory());
    gmres.setDebugStatusTest(history);
    if (options.per_block)
      {
        auto all =
            Teuchos::rcp(new Belos::StatusTestCombo<SC, MV, OP>(Belos::StatusTestCombo<SC, MV, OP>::SEQ));
        for (std::size_t k = 0; k < system.n_blocks(); ++k)
          all->addStatusTest(
              Teuchos::rcp(new Belos::StatusTestGenResSubNorm<SC, MV, OP>(options.tolerance, k)));
        gmres.setUserConvStatusTest(all, Belos::StatusTestCombo<SC, MV, OP>::SEQ);
      }

    Teuchos::Time timer("solve");
    timer.start(true);
    // Belos throws when the residual turns NaN (a preconditioner that blew up): that is a solve
    // that failed, reported as such (report.failure, a NaN residual), never a usable x = 0.
    Belos::ReturnType result = Belos::Unconverged;
    try
      {
        result = gmres.solve();
      }
    catch (const std::exception& e)
      {
        std::string what = e.what();
        what             = what.substr(0, what.find('\n'));
        report.failure   = "GMRES broke down (" + what.substr(0, 160) + ")";
        x.putScalar(std::nan(""));
      }
    report.solve_seconds = timer.stop();
    report.converged     = (result == Belos::Converged);
    report.iterations    = gmres.getNumIters();

    Teuchos::Array<double> bnorm(1);
    system.rhs()->norm2(bnorm);
    const double scale = bnorm[0] > 0 ? bnorm[0] : 1.0;
    report.rhs_norm    = bnorm[0];
    report.residual_history.push_back(1.0);
    for (double r : history->history)
      report.residual_history.push_back(r / scale);

    const auto r_blocks = system.block_residual_norms(x, *system.rhs());
    const auto b_blocks = system.block_norms(*system.rhs());
    double     r2       = 0;
    for (std::size_t k = 0; k < r_blocks.size(); ++k)
      {
        r2 += r_blocks[k] * r_blocks[k];
        report.block_relative_residuals.push_back(b_blocks[k] > 0 ? r_blocks[k] / b_blocks[k] : r_blocks[k]);
      }
    report.relative_residual = std::sqrt(r2) / scale;

    const double mine = peak_resident_mb();
    double       most = 0, sum = 0;
    Teuchos::reduceAll(*system.comm(), Teuchos::REDUCE_MAX, mine, Teuchos::outArg(most));
    Teuchos::reduceAll(*system.comm(), Teuchos::REDUCE_SUM, mine, Teuchos::outArg(sum));
    report.peak_memory_mb_max  = most;
    report.peak_memory_mb_mean = sum / report.ranks;
    return report;
  }

  void print_report(std::ostream& out, const SolveReport& r)
  {
    const auto& p = r.preconditioner;
    out << "preset              " << p.preset << "  (" << p.kind << ")\n"
        << "system              " << r.global_size << " DOFs on " << r.ranks << " rank(s)\n";
    if (!p.levels.empty())
      {
        out << "levels              level        rows    nonzeros  blocks\n";
        for (std::size_t l = 0; l < p.levels.size(); ++l)
          {
            out << "                    " << std::setw(5) << l << std::setw(12) << p.levels[l].rows
                << std::setw(12) << p.levels[l].nonzeros << "  ";
            for (std::size_t k = 0; k < p.levels[l].block_rows.size(); ++k)
              out << (k ? " + " : "") << p.levels[l].block_rows[k];
            if (p.levels[l].ranks > 0)
              out << "  (on " << p.levels[l].ranks << " of " << r.ranks << " ranks)";
            out << "\n";
          }
        out << "operator complexity " << std::fixed << std::setprecision(3) << p.operator_complexity << "\n";
      }
    out << std::defaultfloat;
    if (!p.coarse_solver.empty())
      out << "coarse solver       " << p.coarse_solver << "\n";
    for (const auto& note : p.notes)
      out << "note                " << note << "\n";
    out << "GMRES               " << (r.converged ? "converged" : "NOT converged") << " in " << r.iterations
        << " iterations (tolerance " << r.options.tolerance << (r.options.per_block ? " per block" : "")
        << ", restart " << r.options.restart << ")\n"
        << (r.failure.empty() ? "" : "failure             " + r.failure + "\n")
        << "true residual       " << std::scientific << std::setprecision(3) << r.relative_residual
        << " (relative)\n";
    for (std::size_t k = 0; k < r.block_names.size(); ++k)
      out << "  block " << k << " " << std::left << std::setw(20) << r.block_names[k] << std::right
          << r.block_relative_residuals[k] << "\n";
    out << std::fixed << std::setprecision(3) << "setup seconds       " << p.setup_seconds << "\n";
    if (p.smoother_check_seconds > 0)
      out << "smoother check s    " << p.smoother_check_seconds
          << " (once per run in the apps; not in the set-up)\n";
    out << "solve seconds       " << r.solve_seconds << "\n"
        << std::setprecision(1) << "peak memory per rank max " << r.peak_memory_mb_max << " MB, mean "
        << r.peak_memory_mb_mean << " MB\n"
        << std::defaultfloat;
  }

  std::string to_json(const SolveReport& r)
  {
    const auto&        p = r.preconditioner;
    std::ostringstream s;
    s << "{\"preset\":" << json_string(p.preset) << ",\"kind\":" << json_string(p.kind)
      << ",\"global_size\":" << r.global_size << ",\"ranks\":" << r.ranks
      << ",\"converged\":" << (r.converged ? "true" : "false") << ",\"iterations\":" << r.iterations
      << ",\"tolerance\":" << json_number(r.options.tolerance)
      << ",\"per_block_tolerance\":" << (r.options.per_block ? "true" : "false")
      << ",\"relative_residual\":" << json_number(r.relative_residual) << ",\"blocks\":[";
    for (std::size_t k = 0; k < r.block_names.size(); ++k)
      s << (k ? "," : "") << "{\"name\":" << json_string(r.block_names[k])
        << ",\"relative_residual\":" << json_number(r.block_relative_residuals[k]) << "}";
    s << "],\"residual_history\":[";
    for (std::size_t i = 0; i < r.residual_history.size(); ++i)
      s << (i ? "," : "") << json_number(r.residual_history[i]);
    s << "],\"setup_seconds\":" << json_number(p.setup_seconds)
      << ",\"smoother_check_seconds\":" << json_number(p.smoother_check_seconds)
      << ",\"solve_seconds\":" << json_number(r.solve_seconds)
      << ",\"operator_complexity\":" << json_number(p.operator_complexity)
      << ",\"peak_memory_mb_max\":" << json_number(r.peak_memory_mb_max)
      << ",\"peak_memory_mb_mean\":" << json_number(r.peak_memory_mb_mean)
      << ",\"coarse_solver\":" << json_string(p.coarse_solver) << ",\"levels\":[";
    for (std::size_t l = 0; l < p.levels.size(); ++l)
      {
        s << (l ? "," : "") << "{\"rows\":" << p.levels[l].rows << ",\"nonzeros\":" << p.levels[l].nonzeros
          << ",\"block_rows\":[";
        for (std::size_t k = 0; k < p.levels[l].block_rows.size(); ++k)
          s << (k ? "," : "") << p.levels[l].block_rows[k];
        s << "],\"ranks\":" << p.levels[l].ranks << "}";
      }
    s << "],\"notes\":[";
    for (std::size_t i = 0; i < p.notes.size(); ++i)
      s << (i ? "," : "") << json_string(p.notes[i]);
    s << "]}";
    return s.str();
  }

  void write_json_atomically(const std::string& file, const std::string& json)
  {
    write_file_atomically(file, json + "\n");
  }
} // namespace multigrid

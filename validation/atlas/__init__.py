"""The PRBM error atlas: every PRBM segment model against the exact elastica over its whole input space.

``models`` (the models, their inputs and exact problems), ``lines`` (one line of growing load: the
errors at equal load, split into path and stiffness, and the locus error), ``dataset`` (the build on the
sweep executors, resumable, by code version), ``maps`` and ``expected`` (the error maps the PRBM adapter
reads for its ``outside validity`` flags and expected errors), ``regions`` (each model's 0.5/1/3/5 %
regions), ``claims`` (the seeds' accuracy claims checked), ``refit`` (the (gamma, K_Theta) that minimise
the worst error per region).
"""

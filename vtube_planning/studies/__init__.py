"""The studies: how the method is put to the test, run by run, and what the runs say.

Its modules, from the top of the room down (each imports only those below it):
``campaign_verify`` (a folder's runs and report made again and compared); ``campaign_runner`` (a campaign's runs
handed to an executor) and ``study_plots`` (a study's figures); ``campaign_store`` (a campaign's folder and its
``runs.csv``), ``executors`` (this process, local processes, Dask) and ``crossover`` (the plan against the best
unplanned swarm per cell of a family of tubes, and the report that adds it); ``campaign`` (axes expanded into keyed runs),
``study_report`` (the grid's reports) and ``paper_report`` (the paper's claims per scene); ``study`` (one run of a
study and its modes); ``judging`` (which claims are judged together, on which seeds); ``stats`` (intervals, paired
differences, verdicts, power) and ``seeds`` (which seeds to run). The method itself (geometry, planning, swarm,
baselines) is below the room and knows nothing of it.
"""

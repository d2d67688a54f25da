"""The label vocabulary, one floor below every analysis: codes, classification, exponents, evidence, the judge.

:mod:`.codes` (the class and status codes), :mod:`.classify` (a record's class from its samples), :mod:`.lyapunov`
(exponents and their intervals), :mod:`.evidence` (torus, decay and recurrence tests), :mod:`.anytime` (the judge:
a label decided on evidence within a budget).  The diagram, the regime map and the census read labels from here.
Nothing is imported here: worker processes load only what they use.
"""

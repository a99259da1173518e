"""An inner pytest run for the plugin's tests, in this process: without
hypothesis's plugin and assertion rewriting, which would import and rewrite
their modules in every run."""


def run(pytester, *args):
    return pytester.runpytest_inprocess("-p", "no:cacheprovider", "-p", "no:hypothesispytest",
                                        "--assert=plain", *args)
